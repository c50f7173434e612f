// The designs' parts in treedyn_analysis (their rules, in treedyn_job, are
// listed in registry.cpp): which designs answer more than every design
// does, and which plan their waves from the answers so far. A design with
// either adds one line here.
#include "designs/registry_analysis.hpp"

#include "designs/morris/morris_answer.hpp"
#include "designs/saltelli/saltelli_answer.hpp"
#include "designs/subset_simulation/subset_plan.hpp"

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

std::unique_ptr<ensemble::WavePlan> design_wave_plan(const ensemble::EnsembleSpec& spec) {
  switch (spec.design) {
    case ensemble::Design::subset_simulation:  // with its [ensemble.subset], as the job reader makes sure
      return spec.subset ? std::make_unique<SubsetPlan>(spec) : nullptr;
    default:
      return nullptr;
  }
}

}  // namespace treedyn::designs
