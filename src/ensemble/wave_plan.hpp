// The samples of an ensemble as a sequence of waves.
//
// A wave is a range of sample indices whose inputs are all known when it
// starts. Which wave comes next may depend on the results of the earlier
// ones: rank 0 decides it from every record so far (its ResponseTable, in
// sample-index order, so the decision does not depend on the rank count)
// and the engine sends the decision to every rank. A resumed run replays the
// decisions from its restored records, so a plan keeps no state of its own.
//
// The engine (run_waves, mpi/parallel/wave_phases.cpp) runs every wave the
// same way: its blocks (or, for a wave of chains, whole chains) go out
// through the work queue, finished samples are skipped, each
// sample's record and statistics are kept, and checkpoints cover whatever
// is finished. Before the first wave's other samples it runs that wave's
// first `pilot_samples` as the pilot wave, whose deviations fix the
// statistics' calibration.
//
// make_wave_plan (analysis/wave_plans.hpp) picks the plan of a job: plans
// that decide from the answers so far live beside the answers.
//
// A run's inputs are a pure function of (seed, index) for the fixed designs
// and subset simulation's level 0; a chain's runs are not: each follows from
// the wave's `start` (decided by rank 0 from earlier waves) and the chain's
// own earlier runs. So a design whose runs depend on earlier waves provides
// a WavePlan (first_wave, next_wave and, for waves of chains, chains(): the
// chain's next point from its runs so far); the engine runs each point it
// is given (SampleRunner::run_at). What every design tells the rest of the
// ensemble is its DesignRules (designs/design_rules.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"
#include "output/sample_record.hpp"

namespace treedyn::ensemble {

struct Wave {
  std::uint64_t first = 0, end = 0;  // sample indices [first, end)
  std::string name;                  // for progress lines and messages
  // > 0: the wave's runs are chains of this many runs, [first + c L,
  // first + (c + 1) L) for chain c; one rank runs a chain, in order, since
  // each run's inputs follow from the one before (subset simulation).
  std::uint64_t chain_length = 0;
  std::vector<double> start;  // what the chains start from (designs::LevelStart, packed)
};

// The chains of one wave of chains: where each chain goes from its runs so
// far. Chain c's runs are the wave's [first + c L, first + (c + 1) L).
class ChainWave {
 public:
  virtual ~ChainWave() = default;
  // What a chain decides on from one of its runs' records (subset
  // simulation: the response, signed so that failure is above; NaN when the
  // run failed).
  virtual double value(const SampleRecord& record) const = 0;
  // Runs chain c, in order: run_one(k, u) runs run k at the point u in the unit
  // cube (open) and returns value() of its record; it throws to stop the
  // chain where it is (a resumed run runs the chain again from its start).
  using Run = std::function<double(std::uint64_t k, std::span<const double> u)>;
  virtual void run(std::uint64_t c, const Run& run_one) const = 0;
};

class WavePlan {
 public:
  virtual ~WavePlan() = default;
  virtual Wave first_wave() const = 0;
  // After wave `done`, with `so_far` holding every record up to its end:
  // the next wave, or nullopt when the ensemble is complete. A function of
  // its arguments only.
  virtual std::optional<Wave> next_wave(const Wave& done, const ResponseTable* so_far) const = 0;
  // The chains of `wave`, one of this plan's waves of chains
  // (chain_length > 0); every rank calls it with the wave it was sent.
  virtual std::unique_ptr<const ChainWave> chains(const Wave&) const {
    throw std::logic_error("a wave of chains from a plan that makes none (ensemble/wave_plan.hpp)");
  }
};

// Monte Carlo, Latin hypercube, Sobol and Saltelli: every sample's inputs
// are a pure function of (seed, k), so all of them are one wave.
class FixedDesignPlan final : public WavePlan {
 public:
  explicit FixedDesignPlan(std::uint64_t samples) : samples_(samples) {}
  Wave first_wave() const override { return {0, samples_, "samples", 0, {}}; }
  std::optional<Wave> next_wave(const Wave&, const ResponseTable*) const override { return std::nullopt; }

 private:
  std::uint64_t samples_;
};

}  // namespace treedyn::ensemble
