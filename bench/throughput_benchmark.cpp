// Samples per second, and where a sample's time goes, for every shipped
// example and a 30- and a 100-body chain (bench/jobs/chain30.toml,
// chain100.toml), in one run on one core:
//
//   rhs/sample   right-hand sides per sample (the integrator's count)
//   t_rhs        one right-hand side on that very model (TreeOde::rhs)
//   integration  simulate() alone: no recording, no statistics
//   sample       what a rank does per sample: SampleRunner::run (set-up,
//                integration, recording, reductions, responses), the
//                statistics' update and the record's encoding
//   statistics   EnsembleStatistics::take_sample alone (part of `sample`),
//                the mean over the samples measured: it folds a block of
//                samples every block_samples() calls (up to 64) and only
//                copies in the others
//   recording    run() minus the integration alone: recording, reductions,
//                responses, the final state (part of `sample`)
//   F_int = integration / (rhs/sample x t_rhs), F_ens = sample / integration
//
// Every other figure is a median over the samples measured (samples after
// the pilot, each measured in every way in turn, so that drift hits all
// alike); `sample` is the median run and encoding plus the mean statistics.
//
//   taskset -c 0 ./build/bench/throughput_benchmark [SAMPLES [JOB ...]]
//
// SAMPLES defaults to 32; JOB names limit the table to those rows (for a
// profile of one job), and NAME=PATH adds a row for any job file (an
// integrator or output setting tried out). FOLD_LANES=2 (or 4, 8) in the
// environment folds the statistics that many values at a time instead of
// the widest this CPU runs (block_fold.hpp): the same bits, another speed.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "integrate/simulate.hpp"
#include "integrate/tree_ode.hpp"
#include "job/sample_job.hpp"
#include "persistence/record_codec.hpp"
#include "statistics/ensemble_statistics.hpp"
#include "timing.hpp"

namespace {

using namespace treedyn;
using bench::Clock;
using bench::median;
using bench::seconds_since;

struct Row {
  std::string name;
  int bodies = 0;
  double rhs = 0, t_rhs = 0, integration = 0, sample = 0, statistics = 0, recording = 0;
};

// One right-hand side on the nominal model and state, timed over ~0.2 s.
double time_rhs(const Job& job) {
  TreeOde ode(job.model, job.request.parameterisation, job.request.solver);
  std::vector<double> y(static_cast<std::size_t>(ode.size())), y_dot(y.size());
  ode.pack(job.initial, y);
  long calls = 0;
  const auto start = Clock::now();
  while (seconds_since(start) < 0.2)
    for (int k = 0; k < 100; ++k, ++calls) ode.rhs(0.0, y, y_dot);
  return seconds_since(start) / static_cast<double>(calls);
}

// The statistics as the driver calibrates them: the nominal run and the
// pilot samples' deviations.
statistics::EnsembleStatistics calibrated(ensemble::SampleRunner& runner, const EnsembleSpec& spec,
                                          std::vector<double>& nominal) {
  runner.run(0, true, nominal);
  const std::size_t entries = nominal.size(), columns = runner.layout().columns;
  std::vector<double> low(entries, std::numeric_limits<double>::infinity()), high(entries, -low[0]), trajectory;
  for (std::uint64_t k = 0; k < spec.pilot_samples; ++k)
    if (runner.run(k, false, trajectory).status == SampleStatus::ok)
      for (std::size_t e = 0; e < entries; ++e) {
        low[e] = std::min(low[e], trajectory[e] - nominal[e]);
        high[e] = std::max(high[e], trajectory[e] - nominal[e]);
      }
  return statistics::EnsembleStatistics(
      runner.times(), columns, spec.histogram_bins,
      statistics::calibrate(nominal, low, high, statistics::column_scales(nominal, columns), columns,
                            spec.histogram_bins));
}

Row measure(const std::string& name, const std::string& path, int samples, int fold_lanes) {
  const auto [job, spec] = read_ensemble_job(JobDocument::read(path));
  ensemble::SampleRunner runner(job, spec);
  std::vector<double> nominal, trajectory;
  statistics::EnsembleStatistics stats = calibrated(runner, spec, nominal);
  if (fold_lanes != 0) stats.use_fold_lanes(fold_lanes);
  std::vector<double> rhs, integration, run, statistics, encoding;
  std::vector<char> encoded;
  SimulationRequest bare = job.request;  // nothing observed: no dynamics at the output times
  bare.accelerations_at_outputs = false;
  for (int i = 0; i < samples; ++i) {
    const std::uint64_t k = (spec.pilot_samples + static_cast<std::uint64_t>(i)) % spec.runs;
    runner.prepare(k, false);
    auto t0 = Clock::now();
    const IntegrationOutcome outcome = simulate(runner.model(), runner.initial_state(), bare, {});
    integration.push_back(seconds_since(t0));
    rhs.push_back(static_cast<double>(outcome.stats.rhs_evaluations));

    t0 = Clock::now();
    const SampleRecord record = runner.run(k, false, trajectory);
    run.push_back(seconds_since(t0));
    t0 = Clock::now();
    if (record.status == SampleStatus::ok) stats.take_sample(trajectory);  // as RankResults::keep
    if (i + 1 == samples) (void)stats.mean(0);                             // folds the last, partial block
    statistics.push_back(seconds_since(t0));
    t0 = Clock::now();
    encoded.clear();
    persistence::append_record(record, encoded);
    encoding.push_back(seconds_since(t0));
  }
  double mean_statistics = 0.0;
  for (double t : statistics) mean_statistics += t / static_cast<double>(statistics.size());
  Row row{name,           job.model.n,         median(rhs),
          time_rhs(job),  median(integration), median(run) + mean_statistics + median(encoding),
          mean_statistics};
  row.recording = std::max(0.0, median(run) - row.integration);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const int samples = argc > 1 ? std::max(1, std::atoi(argv[1])) : 32;
  const std::string jobs = TREEDYN_JOBS_DIR, bench = TREEDYN_BENCH_JOBS_DIR;
  const char* lanes = std::getenv("FOLD_LANES");
  const int fold_lanes = lanes != nullptr ? std::atoi(lanes) : 0;
  if (fold_lanes != 0 && !statistics::runs_fold_lanes(fold_lanes)) {
    std::fprintf(stderr, "throughput_benchmark: FOLD_LANES=%s: this CPU folds %d lanes at most (2, 4 or 8)\n", lanes,
                 statistics::widest_fold_lanes());
    return 2;
  }
  std::printf("The statistics' fold: %d lanes.\n\n", fold_lanes != 0 ? fold_lanes : statistics::widest_fold_lanes());
  const std::pair<std::string, std::string> cases[] = {{"spherical_pendulum", jobs + "/spherical_pendulum.toml"},
                                                       {"double_pendulum", jobs + "/double_pendulum.toml"},
                                                       {"kapitza", jobs + "/kapitza.toml"},
                                                       {"chain10", jobs + "/chain10.toml"},
                                                       {"y_tree", jobs + "/y_tree.toml"},
                                                       {"crane_payload", jobs + "/crane_payload.toml"},
                                                       {"chain30", bench + "/chain30.toml"},
                                                       {"chain100", bench + "/chain100.toml"}};
  std::printf(
      "| job | bodies | rhs/sample | t_rhs (us) | integration (ms) | sample (ms) | samples/s | statistics "
      "(%% of sample) | recording (%% of sample) | F_int | F_ens |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::vector<std::pair<std::string, std::string>> rows;
  for (int i = 2; i < argc; ++i) {  // NAME (a row above) or NAME=PATH (any job file)
    const std::string arg = argv[i];
    const auto eq = arg.find('=');
    if (eq != std::string::npos) rows.emplace_back(arg.substr(0, eq), arg.substr(eq + 1));
    for (const auto& c : cases)
      if (c.first == arg) rows.push_back(c);
  }
  if (argc <= 2) rows.assign(std::begin(cases), std::end(cases));
  for (const auto& [name, path] : rows) {
    Row r;
    try {
      r = measure(name, path, samples, fold_lanes);
    } catch (const std::exception& e) {  // a job that cannot be read, or a set-up failure
      std::fprintf(stderr, "throughput_benchmark: %s: %s\n", path.c_str(), e.what());
      return 1;
    }
    std::printf("| %s | %d | %.0f | %.3f | %.3f | %.3f | %.0f | %.1f | %.1f | %.2f | %.2f |\n", r.name.c_str(),
                r.bodies, r.rhs, 1e6 * r.t_rhs, 1e3 * r.integration, 1e3 * r.sample, 1.0 / r.sample,
                100.0 * r.statistics / r.sample, 100.0 * r.recording / r.sample, r.integration / (r.rhs * r.t_rhs),
                r.sample / r.integration);
    std::fflush(stdout);
  }
  return 0;
}
