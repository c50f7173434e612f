#include "analysis/wave_plans.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/answers.hpp"
#include "common/format.hpp"
#include "designs/registry_analysis.hpp"

namespace treedyn::analysis {
namespace {

std::string held(const std::string& target, const std::string& response, double value, double bound,
                 std::uint64_t prefix) {
  char reached[32];
  std::snprintf(reached, sizeof reached, "%.3g", value);
  return target + " of " + response + ": " + reached + " <= " + format_number(bound) + " at " + std::to_string(prefix) +
         " samples";
}

}  // namespace

std::optional<std::string> stop_reason(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                       std::uint64_t prefix) {
  if (!spec.stop) return std::nullopt;
  const StopRule& rule = *spec.stop;
  const std::string& name = spec.responses[rule.response].name;
  const ResponseAnswer a = answer_response(spec, table, rule.response, prefix, false);
  if (rule.exceedance_cov && a.exceedance && a.exceedance->exceeded >= kMinExceedances) {
    const double p = a.exceedance->probability, n = static_cast<double>(a.exceedance->successful);
    const double cov = std::sqrt((1.0 - p) / (n * p));
    if (cov <= *rule.exceedance_cov) return held("exceedance_cov", name, cov, *rule.exceedance_cov, prefix);
  }
  if (rule.mean_sem && a.used >= 2 && a.sem <= *rule.mean_sem)
    return held("mean_sem", name, a.sem, *rule.mean_sem, prefix);
  if (rule.mean_relative_sem && a.used >= 2 && a.mean != 0.0) {
    const double relative = a.sem / std::abs(a.mean);
    if (relative <= *rule.mean_relative_sem)
      return held("mean_relative_sem", name, relative, *rule.mean_relative_sem, prefix);
  }
  return std::nullopt;
}

ensemble::Wave StoppingPlan::wave_from(std::uint64_t first) const {
  const std::uint64_t end = std::min(first + spec_.stop->every, spec_.runs);
  return {first, end, "samples " + std::to_string(first) + " .. " + std::to_string(end - 1), 0, {}};
}

ensemble::Wave StoppingPlan::first_wave() const { return wave_from(0); }

std::optional<ensemble::Wave> StoppingPlan::next_wave(const ensemble::Wave& done,
                                                      const ensemble::ResponseTable* so_far) const {
  if (done.end >= spec_.runs) return std::nullopt;
  if (so_far && stop_reason(spec_, *so_far, done.end)) return std::nullopt;
  return wave_from(done.end);
}

std::unique_ptr<ensemble::WavePlan> make_wave_plan(const EnsembleSpec& spec) {
  if (std::unique_ptr<ensemble::WavePlan> own = designs::design_wave_plan(spec)) return own;
  if (spec.stop) return std::make_unique<StoppingPlan>(spec);
  return std::make_unique<ensemble::FixedDesignPlan>(spec.runs);
}

}  // namespace treedyn::analysis
