// Cost of the per-sample set-up next to the whole sample, on every shipped
// example job (jobs/*.toml, their own [ensemble] sections):
//
//   BM_SampleSetup/<job>  SampleRunner::prepare(k): the nominal parameter
//                         vector and initial state copied, sample k's inputs
//                         drawn and applied, derive_model() with its
//                         physical checks (samples 0, 1, ... in turn).
//   BM_Sample/<job>       SampleRunner::run(k): the same set-up, the
//                         integration and the per-sample reductions.
//
// Both run in the same process, one after the other; at the end a table
// gives set-up / sample per job (CPU time). The target is under 2 % for the
// cheapest example.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"

namespace {

using namespace treedyn;

const std::vector<std::string> kJobs = {"spherical_pendulum", "double_pendulum", "kapitza", "chain10", "y_tree",
                                        "crane_payload"};

struct Loaded {
  Job job;
  EnsembleSpec spec;
};

const Loaded& loaded(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Loaded>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Loaded>();
    slot->job = read_job(std::string(TREEDYN_JOBS_DIR) + "/" + name + ".toml");
    slot->spec = read_ensemble(slot->job);
  }
  return *slot;
}

void BM_SampleSetup(benchmark::State& state, const std::string& name) {
  const Loaded& l = loaded(name);
  ensemble::SampleRunner runner(l.job, l.spec);
  std::uint64_t k = 0;
  for (auto _ : state) {
    std::vector<double> inputs = runner.prepare(k++ % l.spec.runs, false);
    benchmark::DoNotOptimize(inputs.data());
    double mass = runner.model().total_mass;
    benchmark::DoNotOptimize(mass);
  }
}

void BM_Sample(benchmark::State& state, const std::string& name) {
  const Loaded& l = loaded(name);
  ensemble::SampleRunner runner(l.job, l.spec);
  std::vector<double> trajectory;
  std::uint64_t k = 0;
  for (auto _ : state) {
    const SampleRecord r = runner.run(k++ % l.spec.runs, false, trajectory);
    if (r.status != SampleStatus::ok) state.SkipWithError(r.reason.c_str());
    benchmark::DoNotOptimize(trajectory.data());
  }
}

// Prints what the console reporter prints, and keeps the CPU times.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  RatioReporter() : ConsoleReporter(isatty(STDOUT_FILENO) ? OO_ColorTabular : OO_Tabular) {}
  std::map<std::string, double> cpu_ns;
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs)
      if (r.run_type == Run::RT_Iteration || r.aggregate_name == "median")
        cpu_ns[r.run_name.str()] = r.GetAdjustedCPUTime();
  }
};

}  // namespace

int main(int argc, char** argv) {
  for (const std::string& job : kJobs) {
    benchmark::RegisterBenchmark(("BM_SampleSetup/" + job).c_str(), BM_SampleSetup, job)->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("BM_Sample/" + job).c_str(), BM_Sample, job)->Unit(benchmark::kMicrosecond);
  }
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\n%-20s %14s %14s %10s\n", "job", "set-up (us)", "sample (us)", "set-up %");
  for (const std::string& job : kJobs) {
    const auto s = reporter.cpu_ns.find("BM_SampleSetup/" + job), w = reporter.cpu_ns.find("BM_Sample/" + job);
    if (s == reporter.cpu_ns.end() || w == reporter.cpu_ns.end()) continue;
    std::printf("%-20s %14.2f %14.1f %9.3f%%\n", job.c_str(), s->second, w->second, 100.0 * s->second / w->second);
  }
  benchmark::Shutdown();
}
