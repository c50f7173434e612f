// Would integrating B samples together pay? Issue 17's optional batch mode
// is to be built only if it beats 4x today's samples per second on the small
// examples; this measures what it would gain before anyone builds it. It is
// a measurement, not the option:
//
//  * B samples' ODEs form one CVODE system (Adams, fixed-point iteration, the
//    job's tolerances): one step sequence for all of them;
//  * the error norm is the largest of the samples' own WRMS norms, so every
//    step holds each sample's local error to its own tolerance (the global
//    error, measured below, is another matter);
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
// Only CVODE Adams jobs whose orientations need no chart change qualify
// (quaternions: the shipped small examples); the margins are checked after
// every step, and a run that would have needed a change, or that failed
// (alone, batched or as the reference), is flagged in its row.
#include <cvode/cvode.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
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

// As tree_rhs: a non-finite result is recoverable, and no exception gets
// into SUNDIALS' C frames.
int batch_rhs(double t, N_Vector y, N_Vector y_dot, void* user) {
  try {
    const auto& batch = *static_cast<const Batch*>(user);
    for (std::size_t b = 0; b < batch.odes.size(); ++b)
      if (!batch.odes[b]->rhs(t, batch.block(y, b), batch.block(y_dot, b))) return 1;
    return 0;
  } catch (...) {
    return -1;
  }
}

struct Outcome {
  double seconds = 0.0;
  long steps = 0, rhs = 0;  // rhs: the batch's calls (each evaluates every sample)
  std::vector<double> final_state;
  bool ok = true, needs_chart_change = false;
};

using treedyn::sundials::check;  // throws sundials::SetupError with the call's name

// CVODE for the whole batch, with the job's settings.
void* create_cvode(Batch& batch, const SimulationRequest& request, N_Vector y, SUNContext context,
                   SUNNonlinearSolver& solver) {
  const IntegratorSettings& s = request.settings;
  void* memory = treedyn::sundials::check_created(CVodeCreate(CV_ADAMS, context), "CVodeCreate");
  check(CVodeInit(memory, batch_rhs, request.start_time, y), "CVodeInit");
  check(CVodeSStolerances(memory, s.relative_tolerance, s.absolute_tolerance), "CVodeSStolerances");
  check(CVodeSetUserData(memory, &batch), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(memory, s.max_steps), "CVodeSetMaxNumSteps");
  if (s.max_step > 0.0) check(CVodeSetMaxStep(memory, s.max_step), "CVodeSetMaxStep");
  if (s.initial_step > 0.0) check(CVodeSetInitStep(memory, s.initial_step), "CVodeSetInitStep");
  solver = treedyn::sundials::check_created(SUNNonlinSol_FixedPoint(y, 0, context), "SUNNonlinSol_FixedPoint");
  check(CVodeSetNonlinearSolver(memory, solver), "CVodeSetNonlinearSolver");
  return memory;
}

// Every output time up to t: the step's end itself or the batch's dense
// output, then each sample's kinematics and loads there (as simulate()).
// Returns whether any was reached.
bool report_up_to(Batch& batch, void* memory, const std::vector<double>& outputs, std::size_t& next, double t,
                  N_Vector y, N_Vector at) {
  const std::size_t first = next;
  for (; next < outputs.size() && outputs[next] <= t; ++next) {
    N_Vector state = y;
    if (outputs[next] < t) {
      check(CVodeGetDky(memory, outputs[next], 0, at), "CVodeGetDky");
      state = at;
    }
    for (std::size_t b = 0; b < batch.odes.size(); ++b) {
      batch.odes[b]->unpack(outputs[next], batch.block(state, b));
      compute_kinematics_and_loads(batch.models[b], batch.odes[b]->data());
    }
  }
  return next > first;
}

// Whether any sample's chart margin is negative at the step's end (where
// simulate() would change that chart and restart).
bool needs_chart_change(const Batch& batch, N_Vector y, std::vector<double>& margins) {
  for (std::size_t b = 0; b < batch.odes.size(); ++b) {
    batch.odes[b]->chart_margins(batch.block(y, b), margins);
    if (std::any_of(margins.begin(), margins.end(), [](double g) { return g < 0.0; })) return true;
  }
  return false;
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
  std::vector<double> margins(static_cast<std::size_t>(batch.odes.front()->charts()));
  std::size_t next = 0;
  long steps_since_output = 0;  // max_steps is per output interval, as in simulate()
  double t = request.start_time;
  report_up_to(batch, memory, outputs, next, t, y.get(), at.get());
  while (outcome.ok && next < outputs.size()) {
    outcome.ok = CVode(memory, outputs[next], y.get(), &t, CV_ONE_STEP) >= 0;
    if (!outcome.ok) break;
    steps_since_output = report_up_to(batch, memory, outputs, next, t, y.get(), at.get()) ? 0 : steps_since_output + 1;
    outcome.ok = steps_since_output < request.settings.max_steps;
    outcome.needs_chart_change |= needs_chart_change(batch, y.get(), margins);
  }
  outcome.seconds = seconds_since(start);
  // The state at the last output time (the last step ends past it, at a
  // time of its own): what the samples are compared by.
  if (outcome.ok) check(CVodeGetDky(memory, outputs.back(), 0, at.get()), "CVodeGetDky");
  CVodeGetNumSteps(memory, &outcome.steps);
  CVodeGetNumRhsEvals(memory, &outcome.rhs);
  CVodeFree(&memory);
  SUNNonlinSolFree(solver);
  const double* data = N_VGetArrayPointer(at.get());
  outcome.final_state.assign(data, data + length);
  return outcome;
}

struct Row {
  int batch = 0;
  double seconds_per_sample = 0.0, alone_seconds_per_sample = 0.0;  // over the same samples
  double steps_ratio = 0.0, rhs_per_sample = 0.0;
  double error_alone = 0.0, error_batched = 0.0;  // the largest over the samples, in tolerances
  bool ok = true, needs_chart_change = false;
};

// The samples alone (B = 1): their times, steps and final states.
struct Alone {
  std::vector<Outcome> outcomes, references;  // references: tolerances 1000x tighter
};

// The largest |x - reference| / (rtol |reference| + atol) over a state.
double error_in_tolerances(std::span<const double> x, std::span<const double> reference, const IntegratorSettings& s) {
  double largest = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double e =
        std::abs(x[i] - reference[i]) / (s.relative_tolerance * std::abs(reference[i]) + s.absolute_tolerance);
    if (!(e <= largest)) largest = e;  // a NaN stays NaN
  }
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
    alone.references.push_back(integrate(one, tight));
  }
  return alone;
}

Row run_batched(ensemble::SampleRunner& runner, const Job& job, const std::vector<std::uint64_t>& samples,
                const Alone& alone, int size) {
  Row row{size};
  double seconds = 0.0, alone_seconds = 0.0, batch_steps = 0.0, own_steps = 0.0, rhs = 0.0;
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
    for (int b = 0; b < size; ++b) {
      const Outcome& own = alone.outcomes[first + b];
      row.ok &= own.ok && alone.references[first + b].ok;
      row.needs_chart_change |= own.needs_chart_change || alone.references[first + b].needs_chart_change;
      alone_seconds += own.seconds;
    }
    batch_steps += static_cast<double>(out.steps) * size;
    rhs += static_cast<double>(out.rhs) * size;
    for (int b = 0; b < size; ++b) {
      const std::vector<double>& reference = alone.references[first + b].final_state;
      own_steps += static_cast<double>(alone.outcomes[first + b].steps);
      row.error_alone =
          std::max(row.error_alone, error_in_tolerances(alone.outcomes[first + b].final_state, reference, s));
      row.error_batched =
          std::max(row.error_batched,
                   error_in_tolerances(std::span(out.final_state).subspan(b * batch.n, batch.n), reference, s));
    }
  }
  const double counted = static_cast<double>(samples.size() - samples.size() % size);
  row.seconds_per_sample = seconds / counted;
  row.alone_seconds_per_sample = alone_seconds / counted;
  row.steps_ratio = batch_steps / own_steps;
  row.rhs_per_sample = rhs / counted;
  return row;
}

void measure(const std::string& name, const std::string& path, int count) {
  const auto [job, spec] = read_ensemble_job(JobDocument::read(path));
  ensemble::SampleRunner runner(job, spec);
  std::vector<std::uint64_t> samples;
  for (int i = 0; i < count; ++i) samples.push_back((spec.pilot_samples + static_cast<std::uint64_t>(i)) % spec.runs);
  if (job.request.settings.method != Method::cvode_adams) {
    std::printf("| %s | not measured: the batch is CVODE Adams, the job is %s |\n", name.c_str(),
                std::string(treedyn::name(job.request.settings.method)).c_str());
    return;
  }
  const Alone alone = run_alone(runner, job, samples);
  for (int size : {1, 2, 4, 8, 16, 32}) {
    if (size > count) break;
    const Row r = run_batched(runner, job, samples, alone, size);
    std::printf("| %s | %d | %.3f | %.2f | %.2f | %.0f | %.3g | %.3g |%s\n", name.c_str(), r.batch,
                1e3 * r.seconds_per_sample, r.alone_seconds_per_sample / r.seconds_per_sample, r.steps_ratio,
                r.rhs_per_sample, r.error_alone, r.error_batched,
                !r.ok                  ? " a run failed: its errors are not comparable"
                : r.needs_chart_change ? " (a chart change was due)"
                                       : "");
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
  std::printf(
      "| job | B | integration per sample (ms) | speed-up over B = 1 | steps / own steps | rhs per sample "
      "| final-state error alone (tolerances) | in the batch |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const std::vector<std::string> only(argv + std::min(argc, 2), argv + argc);
  for (const std::string& name : only)
    if (std::none_of(std::begin(cases), std::end(cases), [&](const auto& c) { return c.first == name; })) {
      std::fprintf(stderr,
                   "batch_benchmark: no job %s; the jobs are spherical_pendulum, double_pendulum, kapitza, "
                   "heterogeneous\n",
                   name.c_str());
      return 2;
    }
  try {
    for (const auto& [name, path] : cases)
      if (only.empty() || std::find(only.begin(), only.end(), name) != only.end()) measure(name, path, samples);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "batch_benchmark: %s\n", e.what());
    return 1;
  }
  return 0;
}
