// Every sample's status, inputs and responses, by sample index: what rank 0
// knows of the whole ensemble, filled as records arrive (in any order). The
// answers are computed from it, and a design's next wave is decided from it.
#pragma once

#include <cstdint>
#include <vector>

#include "output/sample_record.hpp"

namespace treedyn::ensemble {

class ResponseTable {
 public:
  ResponseTable(std::uint64_t samples, std::size_t inputs, std::size_t responses);
  void add(const SampleRecord& record);
  // The same from stored arrays (e.g. read back from an ensemble file):
  // status per sample, inputs samples x D and responses samples x R, row-major.
  ResponseTable(std::vector<std::int32_t> status, std::vector<double> inputs, std::vector<double> responses,
                std::size_t input_count, std::size_t response_count);

  std::uint64_t samples() const { return status_.size(); }
  // Keeps samples 0 .. n-1 only (a run that a stopping rule ended).
  void truncate(std::uint64_t n);
  std::size_t input_count() const { return inputs_count_; }
  std::size_t response_count() const { return responses_count_; }
  bool ok(std::uint64_t k) const { return status_[k] == static_cast<std::int32_t>(SampleStatus::ok); }
  double input(std::uint64_t k, std::size_t d) const { return inputs_[k * inputs_count_ + d]; }
  double response(std::uint64_t k, std::size_t r) const { return responses_[k * responses_count_ + r]; }

 private:
  std::vector<std::int32_t> status_;
  std::vector<double> inputs_, responses_;
  std::size_t inputs_count_, responses_count_;
};

}  // namespace treedyn::ensemble
