// Would integrating B samples together pay? Issue 17's optional batch mode
// is to be built only if it beats 4x today's samples per second on the small
// examples; this measures what it would gain before anyone builds it. It is
// a measurement, not the option:
//
//  * B samples' ODEs form one CVODE system (Adams, fixed-point iteration, the
//    job's tolerances): one step sequence for all of them;
//  * the error norm is the largest of the samples' own WRMS norms, so every
//    step holds each sample to its own tolerance (at least as accurate as
//    alone);
//  * at every output time, one dense output of the whole batch and each
//    sample's kinematics and loads: what `integration` in
//    throughput_benchmark does for one sample.
//
// Per job and batch size B it prints, per sample: the integration time, the
// speed-up over B = 1 (the same code on one sample: CVODE's arithmetic and
// bits of simulate() for a chart-free job), the batch's steps against the
// mean of the samples' own steps (the lockstep waste: every sample takes the
// steps its hardest companion needs), right-hand sides per sample, and the
// largest error of a final state (at the last output time) alone and in the
// batch, against the same sample integrated with tolerances 1000x tighter,
// in units of the local tolerance rtol |y| + atol.
//
//   taskset -c 0 ./build/bench/batch_benchmark [SAMPLES [JOB ...]]
//
// Only jobs whose orientations need no chart change qualify (quaternions:
// the shipped small examples); a batch that would need one is reported.
#include <cvode/cvode.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "dynamics/pipeline.hpp"
#include "ensemble/sample_runner.hpp"
#include "integrate/state_vector.hpp"
#include "integrate/tree_ode.hpp"
#include "job/sample_job.hpp"
#include "timing.hpp"

namespace {

using namespace treedyn;
using bench::Clock;
using bench::seconds_since;

// CVODE calls a vector operation without user data: the batch's block
// length lives here (the benchmark is one thread, one batch at a time).
std::size_t g_block = 0;

// The largest of the blocks' own WRMS norms (each divided by its own length,
// as N_VWrmsNorm of that sample alone would be).
sunrealtype largest_block_wrms(N_Vector x, N_Vector w) {
  const double* xd = N_VGetArrayPointer(x);
  const double* wd = N_VGetArrayPointer(w);
  const auto length = static_cast<std::size_t>(N_VGetLength(x));
  double largest = 0.0;
  for (std::size_t start = 0; start < length; start += g_block) {
    double sum = 0.0;
    for (std::size_t i = start; i < start + g_block; ++i) {
      const double p = xd[i] * wd[i];
      sum += p * p;
    }
    largest = std::max(largest, std::sqrt(sum / static_cast<double>(g_block)));
  }
  return largest;
}

// B samples: their models (stable addresses: each TreeOde refers to its
// own), initial states and ODEs.
struct Batch {
  std::deque<Model> models;
  std::vector<InitialState> initial;
  std::vector<std::unique_ptr<TreeOde>> odes;
  std::size_t n = 0;  // one sample's state length

  void add(const Model& model, const InitialState& state, const SimulationRequest& request) {
    models.push_back(model);
    initial.push_back(state);
    odes.push_back(std::make_unique<TreeOde>(models.back(), request.parameterisation, request.solver));
    n = static_cast<std::size_t>(odes.back()->size());
  }
  std::span<double> block(N_Vector v, std::size_t b) const { return {N_VGetArrayPointer(v) + b * n, n}; }
};

int batch_rhs(double t, N_Vector y, N_Vector y_dot, void* user) {
  const auto& batch = *static_cast<const Batch*>(user);
  for (std::size_t b = 0; b < batch.odes.size(); ++b)
    if (!batch.odes[b]->rhs(t, batch.block(y, b), batch.block(y_dot, b))) return 1;
  return 0;
}

struct Outcome {
  double seconds = 0.0;
  long steps = 0, rhs = 0;  // rhs: the batch's calls (each evaluates every sample)
  std::vector<double> final_state;
  bool ok = true, needs_chart_change = false;
};

void check(int flag, const char* what) {
  if (flag < 0) {
    std::fprintf(stderr, "batch_benchmark: %s failed (%d)\n", what, flag);
    std::exit(1);
  }
}

// CVODE for the whole batch, with the job's settings.
void* create_cvode(Batch& batch, const SimulationRequest& request, N_Vector y, SUNContext context,
                   SUNNonlinearSolver& solver) {
  const IntegratorSettings& s = request.settings;
  void* memory = CVodeCreate(CV_ADAMS, context);
  check(CVodeInit(memory, batch_rhs, request.start_time, y), "CVodeInit");
  check(CVodeSStolerances(memory, s.relative_tolerance, s.absolute_tolerance), "CVodeSStolerances");
  check(CVodeSetUserData(memory, &batch), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(memory, s.max_steps), "CVodeSetMaxNumSteps");
  if (s.max_step > 0.0) check(CVodeSetMaxStep(memory, s.max_step), "CVodeSetMaxStep");
  if (s.initial_step > 0.0) check(CVodeSetInitStep(memory, s.initial_step), "CVodeSetInitStep");
  solver = SUNNonlinSol_FixedPoint(y, 0, context);
  check(CVodeSetNonlinearSolver(memory, solver), "CVodeSetNonlinearSolver");
  return memory;
}

// Every output time up to t: the batch's dense output, then each sample's
// kinematics and loads there.
void report_up_to(Batch& batch, void* memory, const std::vector<double>& outputs, std::size_t& next, double t,
                  N_Vector y, N_Vector at) {
  for (; next < outputs.size() && outputs[next] <= t; ++next) {
    check(CVodeGetDky(memory, outputs[next], 0, at), "CVodeGetDky");
    for (std::size_t b = 0; b < batch.odes.size(); ++b) {
      batch.odes[b]->unpack(outputs[next], batch.block(outputs[next] < t ? at : y, b));
      compute_kinematics_and_loads(batch.models[b], batch.odes[b]->data());
    }
  }
}

Outcome integrate(Batch& batch, const SimulationRequest& request) {
  g_block = batch.n;
  treedyn::sundials::Context context;
  const auto length = static_cast<sunindextype>(batch.n * batch.odes.size());
  treedyn::sundials::Vector y = treedyn::sundials::new_state_vector(length, context);
  y->ops->nvwrmsnorm = largest_block_wrms;  // CVODE's clones copy it
  treedyn::sundials::Vector at(N_VClone(y.get()));
  for (std::size_t b = 0; b < batch.odes.size(); ++b) batch.odes[b]->pack(batch.initial[b], batch.block(y.get(), b));
  Outcome outcome;
  const auto start = Clock::now();
  SUNNonlinearSolver solver = nullptr;
  void* memory = create_cvode(batch, request, y.get(), context, solver);
  const std::vector<double>& outputs = request.output_times;
  std::size_t next = 0;
  double t = request.start_time;
  report_up_to(batch, memory, outputs, next, t, y.get(), at.get());
  while (outcome.ok && next < outputs.size()) {
    outcome.ok = CVode(memory, outputs[next], y.get(), &t, CV_ONE_STEP) >= 0;
    if (outcome.ok) report_up_to(batch, memory, outputs, next, t, y.get(), at.get());
  }
  outcome.seconds = seconds_since(start);
  // The state at the last output time (the last step ends past it, at a
  // time of its own): what the samples are compared by.
  if (outcome.ok) check(CVodeGetDky(memory, outputs.back(), 0, at.get()), "CVodeGetDky");
  CVodeGetNumSteps(memory, &outcome.steps);
  CVodeGetNumRhsEvals(memory, &outcome.rhs);
  CVodeFree(&memory);
  SUNNonlinSolFree(solver);
  std::vector<double> margins(static_cast<std::size_t>(batch.odes.front()->charts()));
  for (std::size_t b = 0; b < batch.odes.size(); ++b) {
    batch.odes[b]->chart_margins(batch.block(y.get(), b), margins);
    outcome.needs_chart_change |= std::any_of(margins.begin(), margins.end(), [](double g) { return g < 0.0; });
  }
  const double* data = N_VGetArrayPointer(at.get());
  outcome.final_state.assign(data, data + length);
  return outcome;
}

struct Row {
  int batch = 0;
  double seconds_per_sample = 0.0, steps_ratio = 0.0, rhs_per_sample = 0.0;
  double error_alone = 0.0, error_batched = 0.0;  // the largest over the samples, in tolerances
  bool ok = true, needs_chart_change = false;
};

// The samples alone (B = 1): their times, steps and final states.
struct Alone {
  std::vector<Outcome> outcomes, references;  // references: tolerances 1000x tighter
  double seconds = 0.0;
};

// The largest |x - reference| / (rtol |reference| + atol) over a state.
double error_in_tolerances(std::span<const double> x, std::span<const double> reference,
                           const IntegratorSettings& s) {
  double largest = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    largest = std::max(largest, std::abs(x[i] - reference[i]) /
                                    (s.relative_tolerance * std::abs(reference[i]) + s.absolute_tolerance));
  return largest;
}

Alone run_alone(ensemble::SampleRunner& runner, const Job& job, const std::vector<std::uint64_t>& samples) {
  Alone alone;
  SimulationRequest tight = job.request;
  tight.settings.relative_tolerance *= 1e-3;
  tight.settings.absolute_tolerance *= 1e-3;
  for (std::uint64_t k : samples) {
    runner.prepare(k, false);
    Batch one;
    one.add(runner.model(), runner.initial_state(), job.request);
    alone.outcomes.push_back(integrate(one, job.request));
    alone.seconds += alone.outcomes.back().seconds;
    alone.references.push_back(integrate(one, tight));
  }
  return alone;
}

Row run_batched(ensemble::SampleRunner& runner, const Job& job, const std::vector<std::uint64_t>& samples,
                const Alone& alone, int size) {
  Row row{size};
  double seconds = 0.0, batch_steps = 0.0, own_steps = 0.0, rhs = 0.0;
  const auto& s = job.request.settings;
  for (std::size_t first = 0; first + static_cast<std::size_t>(size) <= samples.size(); first += size) {
    Batch batch;
    for (int b = 0; b < size; ++b) {
      runner.prepare(samples[first + b], false);
      batch.add(runner.model(), runner.initial_state(), job.request);
    }
    const Outcome out = integrate(batch, job.request);
    row.ok &= out.ok;
    row.needs_chart_change |= out.needs_chart_change;
    seconds += out.seconds;
    batch_steps += static_cast<double>(out.steps) * size;
    rhs += static_cast<double>(out.rhs) * size;
    for (int b = 0; b < size; ++b) {
      const std::vector<double>& reference = alone.references[first + b].final_state;
      own_steps += static_cast<double>(alone.outcomes[first + b].steps);
      row.error_alone = std::max(row.error_alone, error_in_tolerances(alone.outcomes[first + b].final_state, reference, s));
      row.error_batched = std::max(row.error_batched,
          error_in_tolerances(std::span(out.final_state).subspan(b * batch.n, batch.n), reference, s));
    }
  }
  const double counted = static_cast<double>(samples.size() - samples.size() % size);
  row.seconds_per_sample = seconds / counted;
  row.steps_ratio = batch_steps / own_steps;
  row.rhs_per_sample = rhs / counted;
  return row;
}

void measure(const std::string& name, const std::string& path, int count) {
  const auto [job, spec] = ensemble::read_ensemble_job(JobDocument::read(path));
  ensemble::SampleRunner runner(job, spec);
  std::vector<std::uint64_t> samples;
  for (int i = 0; i < count; ++i) samples.push_back((spec.pilot_samples + static_cast<std::uint64_t>(i)) % spec.samples);
  const Alone alone = run_alone(runner, job, samples);
  const double alone_per_sample = alone.seconds / static_cast<double>(samples.size());
  for (int size : {1, 2, 4, 8, 16, 32}) {
    if (size > count) break;
    const Row r = run_batched(runner, job, samples, alone, size);
    std::printf("| %s | %d | %.3f | %.2f | %.2f | %.0f | %.3g | %.3g |%s\n", name.c_str(), r.batch,
                1e3 * r.seconds_per_sample, alone_per_sample / r.seconds_per_sample, r.steps_ratio, r.rhs_per_sample,
                r.error_alone, r.error_batched,
                !r.ok ? " a batch failed" : r.needs_chart_change ? " (a chart change was due)" : "");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int samples = argc > 1 ? std::max(1, std::atoi(argv[1])) : 32;
  const std::string jobs = TREEDYN_JOBS_DIR, bench = TREEDYN_BENCH_JOBS_DIR;
  const std::pair<std::string, std::string> cases[] = {{"spherical_pendulum", jobs + "/spherical_pendulum.toml"},
                                                       {"double_pendulum", jobs + "/double_pendulum.toml"},
                                                       {"kapitza", jobs + "/kapitza.toml"},
                                                       {"heterogeneous", bench + "/heterogeneous.toml"}};
  std::printf("| job | B | integration per sample (ms) | speed-up over B = 1 | steps / own steps | rhs per sample "
              "| final-state error alone (tolerances) | in the batch |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const std::vector<std::string> only(argv + std::min(argc, 2), argv + argc);
  for (const auto& [name, path] : cases)
    if (only.empty() || std::find(only.begin(), only.end(), name) != only.end()) measure(name, path, samples);
  return 0;
}
