#include "ensemble/sample_rows.hpp"

#include <cstdint>
#include <cstring>
#include <limits>

namespace treedyn::ensemble {
namespace {

template <typename T>
void put(std::vector<unsigned char>& out, const T& value) {
  const std::size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

// `values`, then NaN up to `width`.
void put_row(std::vector<unsigned char>& out, std::span<const double> values, std::size_t width) {
  const std::size_t n = std::min(values.size(), width), at = out.size();
  out.resize(at + width * sizeof(double));
  if (n > 0) std::memcpy(out.data() + at, values.data(), n * sizeof(double));  // data() may be null when empty
  for (std::size_t k = n; k < width; ++k) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(out.data() + at + k * sizeof(double), &nan, sizeof nan);
  }
}

}  // namespace

SampleRows::SampleRows(const EnsembleSpec& spec, const ColumnLayout& layout, std::size_t final_size)
    : inputs_(spec.input_dimensions()), final_size_(final_size), columns_(layout.columns), offset_(layout.offset) {
  for (const auto& names : layout.names) width_.push_back(names.size());
  if (inputs_ > 0) datasets_.push_back({Kind::inputs, inputs_ * sizeof(double)});
  datasets_.push_back({Kind::status, sizeof(std::int32_t)});
  datasets_.push_back({Kind::time_reached, sizeof(double)});
  datasets_.push_back({Kind::integrator_stats, kIntegratorStatFields.size() * sizeof(std::int64_t)});
  datasets_.push_back({Kind::final_state, final_size_ * sizeof(double)});
  if (!spec.responses.empty()) datasets_.push_back({Kind::responses, spec.responses.size() * sizeof(double)});
  for (std::size_t r = 0; r < spec.per_sample.size(); ++r)
    for (std::size_t q = 0; q < width_.size(); ++q)
      datasets_.push_back({Kind::reduction, width_[q] * sizeof(double), r, q});
}

void SampleRows::append(std::size_t i, std::span<const SampleRecord> run, std::vector<unsigned char>& out) const {
  const Dataset& d = datasets_[i];
  out.reserve(out.size() + run.size() * d.row_bytes);
  for (const SampleRecord& r : run) switch (d.kind) {
      case Kind::inputs:
        put_row(out, r.inputs, inputs_);
        break;
      case Kind::status:
        put(out, static_cast<std::int32_t>(r.status));
        break;
      case Kind::time_reached:
        put(out, r.time_reached);
        break;
      case Kind::integrator_stats:
        for (const IntegratorStatField& f : kIntegratorStatFields)
          put(out, static_cast<std::int64_t>(r.stats.*f.member));
        break;
      case Kind::final_state:
        put_row(out, r.final_state, final_size_);
        break;
      case Kind::responses:
        put_row(out, r.responses, d.row_bytes / sizeof(double));
        break;
      case Kind::reduction:
        put_row(out,
                std::span<const double>(r.reductions)
                    .subspan(std::min(r.reductions.size(), d.reduction * columns_ + offset_[d.quantity])),
                width_[d.quantity]);
        break;
    }
}

}  // namespace treedyn::ensemble
