// Morris' own answer for one response: mu*, mu and sigma of the elementary
// effects per unit with their bootstrap intervals (morris_effects.hpp).
// Printed by morris_summary.cpp, written by morris_file.cpp.
#pragma once

#include <memory>

#include "designs/design_answer.hpp"
#include "designs/morris/morris_effects.hpp"

namespace treedyn::designs {

class MorrisAnswer final : public DesignAnswer {
 public:
  MorrisIndices indices;

  void print(std::ostream& out, const EnsembleSpec& spec, const Response& response) const override;
  void write(AnswerWriter& sensitivity, const EnsembleSpec& spec, const Response& response) const override;
};

// The measures of response r from the trajectories `table` holds whole.
std::shared_ptr<const MorrisAnswer> answer_morris(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::size_t r);

}  // namespace treedyn::designs
