// The designs' parts in treedyn_analysis (their rules, in treedyn_job, are
// listed in registry.cpp): which designs answer more than every design
// does, which plan their waves from the answers so far, and how their runs
// that follow from earlier records are replayed. A design with any of these
// adds one line here.
#include "designs/registry_analysis.hpp"

#include "designs/design_rules.hpp"
#include "designs/morris/morris_answer.hpp"
#include "designs/saltelli/saltelli_answer.hpp"
#include "designs/subset_simulation/subset_answer.hpp"
#include "designs/subset_simulation/subset_plan.hpp"
#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {

std::shared_ptr<const DesignAnswer> design_answer(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::size_t r) {
  switch (spec.design) {
    case sampling::Design::saltelli:
      return answer_saltelli(spec, table, r);
    case sampling::Design::morris:
      return answer_morris(spec, table, r);
    default:
      return nullptr;
  }
}

std::unique_ptr<const RunAnswer> run_answer(const EnsembleSpec& spec, const ensemble::ResponseTable& table) {
  switch (spec.design) {
    case sampling::Design::subset_simulation:
      return spec.subset ? answer_rare_event(spec, table) : nullptr;
    default:
      return nullptr;
  }
}

std::optional<std::vector<double>> replayed_point(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::uint64_t k) {
  switch (spec.design) {
    case sampling::Design::subset_simulation:
      if (spec.subset && rules_of(spec.design).follows_records(spec, k)) return subset_uniforms(spec, table, k);
      return std::nullopt;
    default:
      return std::nullopt;
  }
}

std::unique_ptr<ensemble::WavePlan> design_wave_plan(const EnsembleSpec& spec) {
  switch (spec.design) {
    case sampling::Design::subset_simulation:  // with its [ensemble.subset], as the job reader makes sure
      return spec.subset ? std::make_unique<SubsetPlan>(spec) : nullptr;
    default:
      return nullptr;
  }
}

}  // namespace treedyn::designs
