// Each design's rules (src/designs/<name>/*_rules.cpp) against what its
// points (the RunPoints its rules make) actually are, so that a rule cannot drift
// from the design it describes:
//
//  * the registry has rules for every design, and each is that design's;
//  * a design that lets a stopping rule stop it early has nested prefixes:
//    run k's inputs are the same whatever the run count (the premise of a
//    stopping rule); latin_hypercube, which refuses one, does not;
//  * independent_draw picks exactly Saltelli's A and B rows and each Morris
//    trajectory's first run: checked on the points, by which rows share
//    inputs with the row before them;
//  * runs_per_step is the period of that pattern;
//  * nested_prefixes holds exactly where a design's points are nested;
//  * the runs that follow from earlier records (follows_records, adaptive)
//    are subset simulation's runs past level 0, by its own run places, and
//    its answers count level 0 alone (answered_runs) and its P is its own.
#include "designs/design_rules.hpp"

#include <boost/random/sobol.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "designs/sample_design.hpp"
#include "designs/subset_simulation/subset_simulation.hpp"
#include "job/ensemble_spec.hpp"
#include "sampling/design.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::sampling;
using treedyn::designs::rules_of;
using treedyn::designs::SampleDesign;

constexpr unsigned kInputs = 3;

EnsembleSpec spec_of(Design design, std::uint64_t runs) {
  EnsembleSpec s;
  s.design = design;
  s.runs = runs;
  for (unsigned d = 0; d < kInputs; ++d) s.sobol_units.push_back({"x" + std::to_string(d), {d}});
  if (design == Design::morris) s.morris = treedyn::designs::MorrisSpec{};  // radial steps
  return s;
}

SampleDesign points_of(const EnsembleSpec& s) { return SampleDesign(s.design, 11, s.runs, kInputs, {}, s.morris); }

// How many of the inputs of run k equal those of run k - 1.
unsigned shared_with_previous(const SampleDesign& points, std::uint64_t k) {
  std::vector<double> a(kInputs), b(kInputs);
  points.point(k - 1, a);
  points.point(k, b);
  unsigned same = 0;
  for (unsigned d = 0; d < kInputs; ++d) same += a[d] == b[d] ? 1u : 0u;
  return same;
}

// The registry: each design's own rules, and no two designs claiming one table.
TEST(DesignRules, EveryDesignHasItsOwnRules) {
  std::set<std::string_view> tables;
  for (const auto& [design, text] : kDesignNames) {
    EXPECT_EQ(rules_of(design).design(), design) << text;
    const std::string_view table = rules_of(design).table();
    if (!table.empty()) {
      EXPECT_TRUE(tables.insert(table).second) << text << " claims [ensemble." << table << "]";
    }
  }
  EXPECT_EQ(tables, (std::set<std::string_view>{"morris", "subset"}));
}

TEST(DesignRules, ADesignAStoppingRuleMayStopHasNestedPrefixes) {
  for (Design design : {Design::monte_carlo, Design::latin_hypercube, Design::sobol, Design::saltelli}) {
    const std::uint64_t step = rules_of(design).runs_per_step(spec_of(design, 0));
    const EnsembleSpec small = spec_of(design, 8 * step), large = spec_of(design, 32 * step);
    const SampleDesign a = points_of(small), b = points_of(large);
    bool nested = true;
    std::vector<double> u(kInputs), v(kInputs);
    for (std::uint64_t k = 0; k < small.runs; ++k) {
      a.point(k, u);
      b.point(k, v);
      nested = nested && u == v;
    }
    EXPECT_EQ(rules_of(design).why_no_stopping_rule().empty(), nested) << name(design);
  }
  EXPECT_FALSE(rules_of(Design::subset_simulation).why_no_stopping_rule().empty());
  EXPECT_FALSE(rules_of(Design::morris).why_no_stopping_rule().empty());
}

// A response's convergence table is one where the first runs are a design of
// their own: the designs whose points are nested (Morris' whole
// trajectories too); subset simulation's answers count level 0, Monte Carlo.
TEST(DesignRules, NestedPrefixesAreTheDesignsWhosePointsAreNested) {
  for (Design design :
       {Design::monte_carlo, Design::latin_hypercube, Design::sobol, Design::saltelli, Design::morris}) {
    const std::uint64_t step = rules_of(design).runs_per_step(spec_of(design, 0));
    const SampleDesign a = points_of(spec_of(design, 8 * step)), b = points_of(spec_of(design, 32 * step));
    bool nested = true;
    std::vector<double> u(kInputs), v(kInputs);
    for (std::uint64_t k = 0; k < 8 * step; ++k) {
      a.point(k, u);
      b.point(k, v);
      nested = nested && u == v;
    }
    EXPECT_EQ(rules_of(design).nested_prefixes(), nested) << name(design);
  }
  EXPECT_TRUE(rules_of(Design::subset_simulation).nested_prefixes());
}

TEST(DesignRules, OnlySubsetSimulationsLaterLevelsFollowFromEarlierRecords) {
  EnsembleSpec s = spec_of(Design::subset_simulation, 0);
  s.samples = 40;
  s.subset = SubsetSpec{0, 0.1, 3};
  s.runs = s.samples * (1 + 3 * 9 / 10);  // N (1 + (1 - p0) max_levels)
  treedyn::designs::SubsetSettings settings;
  settings.samples = s.samples;
  settings.level_probability = 0.1;
  settings.max_levels = 3;
  const auto& rules = rules_of(Design::subset_simulation);
  for (std::uint64_t k = 0; k < s.runs; ++k)
    EXPECT_EQ(rules.follows_records(s, k), treedyn::designs::run_place(settings, k).level > 0) << "run " << k;
  EXPECT_TRUE(rules.adaptive(s));
  EXPECT_EQ(rules.answered_runs(s, s.runs), s.samples);
  EXPECT_EQ(rules.answered_runs(s, 7), 7u);
  EXPECT_TRUE(rules.answers_probability(s, 0));
  EXPECT_FALSE(rules.answers_probability(s, 1));
  for (const auto& [design, text] : kDesignNames) {
    if (design == Design::subset_simulation) continue;
    const EnsembleSpec other = spec_of(design, 64);
    EXPECT_FALSE(rules_of(design).adaptive(other)) << text;
    EXPECT_EQ(rules_of(design).answered_runs(other, 64), 64u) << text;
    EXPECT_FALSE(rules_of(design).answers_probability(other, 0)) << text;
  }
  EXPECT_FALSE(rules_of(Design::monte_carlo).adaptive(spec_of(Design::monte_carlo, 0)));  // no runs at all
}

// A run that repeats some of the run before's inputs (Saltelli's AB rows
// repeat A's but one; a Morris step keeps all but one unit) is not an
// independent draw; the first of each step is, and so is B, which shares
// none of A's.
TEST(DesignRules, IndependentDrawsAreTheRunsThatShareNoInputsWithTheRunBefore) {
  for (const auto& [design, text] : kDesignNames) {
    if (design == Design::subset_simulation) continue;  // its later levels are chains, not points
    const EnsembleSpec s = spec_of(design, 0);
    const std::uint64_t step = rules_of(design).runs_per_step(s);
    const EnsembleSpec sized = spec_of(design, 16 * step);
    const SampleDesign points = points_of(sized);
    std::uint64_t independent = 0;
    for (std::uint64_t k = 1; k < sized.runs; ++k) {
      const bool shares = shared_with_previous(points, k) > 0;
      EXPECT_EQ(rules_of(design).independent_draw(sized, k), !shares) << text << " run " << k;
      independent += rules_of(design).independent_draw(sized, k) ? 1 : 0;
    }
    const std::uint64_t per_step = design == Design::saltelli ? 2 : 1;  // A and B
    EXPECT_EQ(independent + 1, 16 * per_step) << text;                  // run 0 is one
  }
}

// What the Sobol' generator cannot make is refused with the design's name,
// only by the designs that use it: D dimensions (saltelli and radial morris:
// 2D) within Boost's tables, at most 2^32 - 1 (base) points; and one unit per
// input dimension for any design.
TEST(DesignRules, PointsBeyondTheGeneratorAreRefusedNamingTheDesign) {
  constexpr unsigned kMax = boost::random::detail::qrng_tables::sobol::max_dimension;
  auto refusal = [](Design design, std::uint64_t runs, unsigned dimensions,
                    const std::optional<treedyn::designs::MorrisSpec>& morris = {}) -> std::string {
    try {
      SampleDesign(design, 1, runs, dimensions, {}, morris);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(refusal(Design::sobol, 8, kMax + 1), "sobol design: at most " + std::to_string(kMax) + " Sobol dimensions");
  EXPECT_EQ(refusal(Design::sobol, 8, kMax), "");
  EXPECT_EQ(refusal(Design::saltelli, 8 * (kMax / 2 + 3), kMax / 2 + 1).rfind("saltelli design: at most", 0), 0u);
  EXPECT_EQ(refusal(Design::saltelli, 8 * (kMax / 2 + 2), kMax / 2), "");
  EXPECT_EQ(refusal(Design::morris, 8 * (kMax / 2 + 2), kMax / 2 + 1).rfind("morris design: at most", 0), 0u);
  const treedyn::designs::MorrisSpec grid{8, false, 4};  // no Sobol' points: no such limit
  EXPECT_EQ(refusal(Design::morris, 8 * (kMax / 2 + 2), kMax / 2 + 1, grid), "");
  EXPECT_EQ(refusal(Design::monte_carlo, 8, kMax + 1), "");
  EXPECT_EQ(refusal(Design::sobol, std::uint64_t{1} << 32, 2), "sobol design: at most 2^32 - 1 Sobol points");
  EXPECT_EQ(refusal(Design::sobol, (std::uint64_t{1} << 32) - 1, 2), "");
  EXPECT_EQ(refusal(Design::saltelli, (std::uint64_t{1} << 32) * 4, 2),
            "saltelli design: at most 2^32 - 1 Sobol points");
  EXPECT_THROW(SampleDesign(Design::saltelli, 1, 8, 3, {0, 1}), std::invalid_argument);  // 2 units for 3 inputs
}

TEST(DesignRules, StepsAreSaltellisBlocksAndMorrisTrajectories) {
  EXPECT_EQ(rules_of(Design::saltelli).runs_per_step(spec_of(Design::saltelli, 0)), kInputs + 2u);
  EXPECT_EQ(rules_of(Design::morris).runs_per_step(spec_of(Design::morris, 0)), kInputs + 1u);
  for (Design design : {Design::monte_carlo, Design::latin_hypercube, Design::sobol, Design::subset_simulation})
    EXPECT_EQ(rules_of(design).runs_per_step(spec_of(design, 0)), 1u) << name(design);
}

}  // namespace
