// The [ensemble] section of a job file.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "designs/morris/morris_spec.hpp"
#include "job/job.hpp"
#include "output/response.hpp"
#include "sampling/design.hpp"
#include "sampling/normal_copula.hpp"
#include "sampling/perturbation.hpp"

namespace treedyn {

// [ensemble.stop]: stop at the first check point (every `every` samples, or
// `every` whole Saltelli blocks) where one of the targets holds for the
// response, evaluated on the samples before it in index order.
struct StopRule {
  std::size_t response = 0;                 // index into EnsembleSpec::responses
  std::optional<double> exceedance_cov;     // sqrt((1 - P) / (n P)), once kMinExceedances are seen
  std::optional<double> mean_sem;           // standard error of the mean, in the response's units
  std::optional<double> mean_relative_sem;  // standard error / |mean|
  std::uint64_t every = 0;                  // runs between check points
};
// An exceedance coefficient of variation counts only with this many
// exceedances seen: with fewer, sqrt((1 - P) / (n P)) is itself too uncertain.
inline constexpr std::uint64_t kMinExceedances = 10;

// [ensemble.subset] of design = "subset_simulation": `samples` runs per
// level, the response's limit as the failure, levels of probability p0.
struct SubsetSpec {
  std::size_t response = 0;        // index into EnsembleSpec::responses (it has a limit)
  double level_probability = 0.1;  // p0
  int max_levels = 10;             // levels after level 0, at most
};

// What Saltelli's design moves together in one AB block, and what one
// Sobol' index is of: a declared [[ensemble.group]], an orientation
// perturbation's three inputs (when groups are declared), or one input.
// Without [[ensemble.group]] every input is a unit of its own: the
// per-input design.
struct SobolUnit {
  std::string name;              // the group's, the orientation's target, or the input's name
  std::vector<unsigned> inputs;  // input dimensions, ascending
};

struct EnsembleSpec {
  std::uint64_t runs = 100;     // the runs it makes: saltelli samples (U + 2), morris samples (U + 1)
  std::uint64_t samples = 100;  // as the job gives it: samples, saltelli's base size N, morris' trajectories r
  std::uint64_t seed = 1;
  sampling::Design design = sampling::Design::monte_carlo;
  std::vector<double> quantiles{0.05, 0.5, 0.95};
  int histogram_bins = 128;          // per output time and component (quantiles and histograms)
  std::uint64_t pilot_samples = 32;  // samples 0..pilot-1 fix the histogram ranges
  std::uint64_t block_size = 4;      // samples handed out per work-queue request
  std::vector<sampling::Perturbation> perturbations;
  std::vector<Reduction> per_sample{Reduction::final, Reduction::min, Reduction::max, Reduction::argmin_time,
                                    Reduction::argmax_time};
  std::vector<Response> responses;
  std::uint64_t store_trajectories = 0;       // full trajectories of samples 0 .. M-1
  int bootstrap_resamples = 1000;             // for the Sobol' index intervals
  std::optional<StopRule> stop;               // `runs` is then the most the run makes
  std::optional<SubsetSpec> subset;           // design = "subset_simulation": runs = the most it makes
  std::optional<designs::MorrisSpec> morris;  // design = "morris": runs = trajectories x (U + 1)
  std::vector<SobolUnit> sobol_units;  // Saltelli's and Morris' units (read_ensemble fills them for every design)
  bool grouped = false;                // sobol_units are not the inputs ([[ensemble.group]], morris' lists)
  std::vector<sampling::InputCorrelation> correlations;

  unsigned input_dimensions() const;
  std::vector<std::string> input_names() const;
  // SI unit of every input column ("1" for a scale factor).
  std::vector<std::string> input_units() const;
  // Saltelli's units (every input alone when sobol_units is empty), the unit
  // of each input dimension, and the runs per base sample, U + 2.
  unsigned unit_count() const;
  std::vector<unsigned> unit_of_input() const;
  std::uint64_t saltelli_block() const { return sampling::saltelli_block(unit_count()); }
  // The units' names (the inputs' where every unit is one input), and each
  // unit's inputs as one comma-separated text.
  std::vector<std::string> unit_names() const;
  std::vector<std::string> unit_inputs() const;
};

// Memory the statistics need on every rank: bin counters, sums, minima and
// maxima for every output time and column.
double statistics_bytes(const Job& job, const EnsembleSpec& spec);

// Bytes in the output file of the per-sample reductions and of the stored
// trajectories.
double per_sample_bytes(const Job& job, const EnsembleSpec& spec);
double stored_trajectory_bytes(const Job& job, const EnsembleSpec& spec);
// Peak memory of the responses' analysis on rank 0.
double answers_bytes(const EnsembleSpec& spec);

// Reads [ensemble] from the job's text; throws JobError like the job reader.
// A job without [ensemble] is refused (the ensemble needs its sample count).
EnsembleSpec read_ensemble(const Job& job);

}  // namespace treedyn
