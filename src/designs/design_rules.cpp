#include "designs/design_rules.hpp"

#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

void DesignRules::read_runs(const TomlView&, EnsembleSpec& s, std::uint64_t) const { s.runs = s.samples; }

std::uint64_t DesignRules::first_wave_runs(const EnsembleSpec& s) const { return s.runs; }

// Its last run follows from earlier records when any does: a later run is
// never drawn from the seed alone once one before it was not.
bool DesignRules::adaptive(const EnsembleSpec& s) const { return s.runs > 0 && follows_records(s, s.runs - 1); }

}  // namespace treedyn::designs
