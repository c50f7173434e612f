// Which designs answer more than every design does, and how. A design with
// an answer of its own adds one line here (its rules: registry.cpp).
#include "designs/design_answer.hpp"
#include "designs/morris/morris_answer.hpp"
#include "designs/saltelli/saltelli_answer.hpp"

namespace treedyn::designs {

std::shared_ptr<const DesignAnswer> design_answer(const ensemble::EnsembleSpec& spec,
                                                  const ensemble::ResponseTable& table, std::size_t r) {
  switch (spec.design) {
    case ensemble::Design::saltelli:
      return answer_saltelli(spec, table, r);
    case ensemble::Design::morris:
      return answer_morris(spec, table, r);
    default:
      return nullptr;
  }
}

}  // namespace treedyn::designs
