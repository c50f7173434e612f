#include "ensemble/response_table.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace treedyn::ensemble {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

ResponseTable::ResponseTable(std::uint64_t samples, std::size_t inputs, std::size_t responses)
    : status_(samples, static_cast<std::int32_t>(SampleStatus::integration_failed)),
      inputs_(samples * inputs, kNaN),
      responses_(samples * responses, kNaN),
      inputs_count_(inputs),
      responses_count_(responses) {}

ResponseTable::ResponseTable(std::vector<std::int32_t> status, std::vector<double> inputs,
                             std::vector<double> responses, std::size_t input_count, std::size_t response_count)
    : status_(std::move(status)),
      inputs_(std::move(inputs)),
      responses_(std::move(responses)),
      inputs_count_(input_count),
      responses_count_(response_count) {
  if (inputs_.size() != status_.size() * inputs_count_ || responses_.size() != status_.size() * responses_count_)
    throw std::invalid_argument("ResponseTable: inputs or responses are not samples x columns");
}

void ResponseTable::add(const SampleRecord& record) {
  const std::uint64_t k = record.index;
  status_[k] = static_cast<std::int32_t>(record.status);
  for (std::size_t d = 0; d < std::min(inputs_count_, record.inputs.size()); ++d)
    inputs_[k * inputs_count_ + d] = record.inputs[d];
  for (std::size_t r = 0; r < std::min(responses_count_, record.responses.size()); ++r)
    responses_[k * responses_count_ + r] = record.responses[r];
}

void ResponseTable::truncate(std::uint64_t n) {
  if (n >= samples()) return;
  status_.resize(n);
  inputs_.resize(n * inputs_count_);
  responses_.resize(n * responses_count_);
}

}  // namespace treedyn::ensemble
