#include "designs/design_rules.hpp"

#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

void DesignRules::read_runs(const TomlView&, ensemble::EnsembleSpec& s, std::uint64_t) const { s.runs = s.samples; }

std::uint64_t DesignRules::first_wave_runs(const ensemble::EnsembleSpec& s) const { return s.runs; }

}  // namespace treedyn::designs
