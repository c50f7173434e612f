// The per-sample datasets of numbers under /samples (all but the stored
// trajectories) as rows made from records: one layout, shared by rank 0's
// writer (hdf5/ensemble_file.hpp) and the senders that assemble and compress
// whole chunks themselves (hdf5/unit_chunks.hpp), so that both make the same
// bytes.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "job/ensemble_spec.hpp"
#include "output/quantities.hpp"
#include "output/sample_record.hpp"

namespace treedyn::ensemble {

class SampleRows {
 public:
  enum class Kind { inputs, status, time_reached, integrator_stats, final_state, responses, reduction };
  struct Dataset {
    Kind kind;
    std::size_t row_bytes = 0;
    std::size_t reduction = 0, quantity = 0;  // Kind::reduction: spec.per_sample[reduction] of layout quantity
  };

  // In the order the writer creates them: inputs (when any), status,
  // time_reached, integrator_stats, final_state, responses (when any), then
  // each reduction's quantities.
  SampleRows(const EnsembleSpec& spec, const ColumnLayout& layout, std::size_t final_size);
  const std::vector<Dataset>& datasets() const { return datasets_; }

  // The rows of consecutive samples `run`, of dataset `i`, appended to `out`
  // as the file stores them (native numbers; a short inputs or final-state
  // row padded with NaN).
  void append(std::size_t i, std::span<const SampleRecord> run, std::vector<unsigned char>& out) const;

 private:
  std::size_t inputs_, final_size_, columns_;
  std::vector<std::size_t> offset_, width_;  // of each layout quantity
  std::vector<Dataset> datasets_;
};

}  // namespace treedyn::ensemble
