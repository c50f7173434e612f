// Saltelli's own answer for one response: the Sobol' indices of every unit
// (an input, or a group), from the complete blocks of U + 2 runs, their
// convergence on the first 4, 8, 16, ... base points, and whether N is
// enough. Printed by saltelli_summary.cpp, written by saltelli_file.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "designs/design_answer.hpp"
#include "designs/saltelli/sobol_indices.hpp"
#include "ensemble/response_table.hpp"

namespace treedyn::designs {

// The Sobol' indices of the first `base_points` base points (their complete
// blocks: indices.base_samples of them).
struct SobolPrefix {
  std::uint64_t base_points = 0;
  SobolIndices indices;
};

// "Is N enough for the indices?": the widest 95 % interval (within [0, 1])
// of a total index among the units that matter (total index >= kIndexMatters, and at least
// the largest), enough when within kIndexIntervalWidth; `needed` is about
// the base points that would make it so, N (widest / kIndexIntervalWidth)^2.
inline constexpr double kIndexMatters = 0.05;
inline constexpr double kIndexIntervalWidth = 0.1;
// Indices resting on fewer than this share of the blocks run are unreliable:
// the failed runs' blocks are left out, and failures that depend on the
// inputs bias what remains.
inline constexpr double kReliableBlockShare = 0.8;
struct IndexVerdict {
  double widest = 0.0;   // NaN without intervals
  std::size_t unit = 0;  // whose interval it is
  double needed = 0.0;   // base points
  bool enough = false;
};
IndexVerdict index_verdict(const SobolIndices& s);

class SaltelliAnswer final : public DesignAnswer {
 public:
  SobolIndices indices;                  // of every complete block
  std::uint64_t blocks = 0;              // base points run; indices.base_samples of them complete
  std::vector<SobolPrefix> convergence;  // on 4, 8, 16, ... base points, and all

  // Fewer than kReliableBlockShare of the blocks run are complete.
  bool unreliable() const;
  void print(std::ostream& out, const EnsembleSpec& spec, const Response& response) const override;
  void write(AnswerWriter& sensitivity, const EnsembleSpec& spec, const Response& response) const override;
};

// The indices of response r from every whole block of `table`.
std::shared_ptr<const SaltelliAnswer> answer_saltelli(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                      std::size_t r);

}  // namespace treedyn::designs
