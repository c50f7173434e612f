// The top level of a job file: sections, integrator, output, and the model's
// validation mapped back to the place in the file.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "dynamics/acceleration_solver.hpp"
#include "dynamics/data.hpp"
#include "dynamics/mass_matrix.hpp"
#include "dynamics/pipeline.hpp"
#include "job/job.hpp"
#include "job/readers.hpp"
#include "job/toml_document.hpp"
#include "output/quantities.hpp"

namespace treedyn {
namespace {

constexpr double kSmallestRelativeTolerance = 1e-15;

void read_integrator(const TomlView& t, SimulationRequest& r) {
  t.check_keys({"method", "parameterisation", "solver", "rtol", "atol", "max_steps", "max_step", "initial_step"});
  if (auto m = t.string("method"); m && !parse_method(*m, r.settings.method))
    t.fail("method", "\"" + *m + "\" is not a method; allowed: " + choices(kMethodNames));
  if (auto p = t.string("parameterisation"); p && !parse_parameterisation(*p, r.parameterisation))
    t.fail("parameterisation", "\"" + *p + "\" is not a parameterisation; allowed: " + choices(kParameterisationNames));
  if (auto s = t.string("solver"); s && !parse_acceleration_solver(*s, r.solver))
    t.fail("solver", "\"" + *s + "\" is not an acceleration solver; allowed: " + choices(kAccelerationSolverNames));
  auto positive = [&](std::string_view key, double& value) {
    if (auto v = t.number(key)) {
      if (!(*v > 0.0)) t.fail(key, "must be positive");
      value = *v;
    }
  };
  positive("rtol", r.settings.relative_tolerance);
  // Below ~5 machine epsilons no step can meet the error test: the
  // integrator would stop at t = 0 with too_much_accuracy.
  if (r.settings.relative_tolerance < kSmallestRelativeTolerance)
    t.fail("rtol", format_number(r.settings.relative_tolerance) +
                       " asks for more than double precision can give: at least 1e-15 (about 5 machine epsilons)");
  positive("atol", r.settings.absolute_tolerance);
  positive("max_step", r.settings.max_step);
  positive("initial_step", r.settings.initial_step);
  if (auto n = t.integer("max_steps")) {
    if (*n < 1) t.fail("max_steps", "must be a positive integer");
    r.settings.max_steps = *n;
  }
}

std::vector<double> read_output_times(const TomlView& t) {
  const bool explicit_list = t.has("times");
  if (explicit_list && (t.has("end_time") || t.has("step")))
    t.fail("times", "give either 'times' or 'end_time' with 'step', not both");
  if (explicit_list) {
    std::vector<double> times = *t.numbers("times");
    if (times.empty()) t.fail("times", "must list at least one time (s)");
    for (std::size_t k = 0; k < times.size(); ++k)
      if (times[k] < 0.0 || (k > 0 && times[k] < times[k - 1])) t.fail("times", "must be >= 0 and non-decreasing (s)");
    return times;
  }
  const auto end = t.number("end_time");
  if (!end) t.fail("end_time", "missing required field: the end time in s (or give 'times')");
  if (!(*end > 0.0)) t.fail("end_time", format_number(*end) + " is not allowed; the end time must be > 0 s");
  const auto step = t.number("step");
  if (!step) t.fail("step", "missing required field: the output step in s");
  if (!(*step > 0.0)) t.fail("step", "must be > 0 s");
  if (*step > *end)
    t.fail("step", "the output step " + format_number(*step) + " s is larger than the end time " + format_number(*end) +
                       " s; it must be at most end_time");
  const double ratio = std::floor(*end / *step * (1.0 + 1e-12));
  if (!(ratio <= 10'000'000.0))  // checked as a double: the cast below would overflow
    t.fail("step", "more than 10 million output times; use a larger step");
  const auto count = static_cast<long>(ratio);
  std::vector<double> times;
  for (long k = 0; k <= count; ++k) times.push_back(static_cast<double>(k) * *step);
  if (times.back() < *end * (1.0 - 1e-12)) times.push_back(*end);
  times.back() = std::min(times.back(), *end);
  return times;
}

OutputSpec read_output(const TomlView& t, const ModelSpec& model, SimulationRequest& r) {
  t.check_keys({"end_time", "step", "times", "quantities", "point"});
  r.output_times = read_output_times(t);
  OutputSpec out;
  for (const TomlView& p : t.table_array("point")) {
    p.check_keys({"name", "body", "point"});
    OutputPoint point;
    point.name = p.required_string("name");
    point.body = p.required_string("body");
    point.point = p.vec3("point").value_or(Vec3::Zero());
    for (std::size_t b = 0; b < model.bodies.size(); ++b)
      if (model.bodies[b].name == point.body) point.body_index = static_cast<int>(b);
    if (point.body_index < 0) p.fail("body", "'" + point.body + "' is not a body of the model");
    out.points.push_back(point);
  }
  if (const toml::node* q = t.table().get("quantities")) {
    const toml::array* list = q->as_array();
    if (!list) t.fail("quantities", "expected an array of quantity names");
    for (const toml::node& e : *list) {
      const auto name = e.value<std::string>();
      std::string allowed;
      for (const QuantityInfo& info : quantity_catalogue()) allowed += " " + std::string(info.name);
      if (!name || !find_quantity(*name)) t.fail_at(&e, "quantities", "unknown quantity; allowed:" + allowed);
      out.quantities.push_back(*name);
    }
    const bool wants_points =
        std::find(out.quantities.begin(), out.quantities.end(), "point_position") != out.quantities.end();
    if (wants_points && out.points.empty())
      t.fail("quantities", "\"point_position\" needs at least one [[output.point]]");
  } else {
    for (const QuantityInfo& info : quantity_catalogue())
      if (info.name != "point_position" || !out.points.empty()) out.quantities.emplace_back(info.name);
  }
  return out;
}

// The equations once at the start, as the integrator will see them: a model
// whose values are each fine but overflow together, or an initial state that
// does, is refused here, naming the first body whose w' is not finite,
// instead of failing at t = 0 after all the set-up.
template <class Where>
void require_finite_start(const Job& job, const Where& where, const std::string& file) {
  const Model& model = job.model;
  if (static_cast<int>(job.initial.rotation.size()) != model.n ||
      static_cast<int>(job.initial.angular_velocity.size()) != model.n)
    return;  // the state reader reports that itself
  Data data(model);
  data.time = job.request.start_time;
  for (int i = 0; i < model.n; ++i) {
    data.rotation[i] = job.initial.rotation[model.tree().user_index[i]];
    data.angular_velocity[i] = job.initial.angular_velocity[model.tree().user_index[i]];
  }
  if (forward_dynamics(model, data)) return;
  for (int u = 0; u < model.n; ++u) {
    const int i = model.tree().regular_index[u];
    if (data.angular_acceleration.segment<3>(3 * i).allFinite() && u + 1 < model.n) continue;
    const std::string name = model.tree().user_body_name(u);
    const auto it = where.find(name);
    throw JobError(
        file, it != where.end() ? line_of(*it->second) : 0, it != where.end() ? column_of(*it->second) : 0, "",
        "body '" + name + "': the equations of motion are not finite at t = " + format_number(job.request.start_time) +
            " s with the initial state (values that overflow double precision together); "
            "give SI values of a physical size");
  }
}

}  // namespace

Job read_job(const JobDocument& document) {
  const std::string& file = document.file();
  const TomlView root(root_table(document), "", file);
  root.check_keys({"title", "environment", "base", "body", "chain", "force", "moment", "integrator", "output",
                   "ensemble", "sample"});
  // [ensemble] is read by treedyn-ensemble, [sample] by job/sample_job.cpp.

  Job job;
  job.file = file;
  job.text = document.text();
  job.document = document;
  job.title = root.string("title").value_or("");

  ModelSpec spec;
  ReadBodies bodies = read_bodies(root);
  spec.bodies = std::move(bodies.bodies);
  spec.joints = std::move(bodies.joints);
  if (auto env = root.subtable("environment")) {
    env->check_keys({"gravity"});
    spec.gravity = env->vec3("gravity").value_or(spec.gravity);
  }
  if (auto base = root.subtable("base")) {
    spec.base_motion = read_base(*base);
    bodies.where[kBaseName] = &base->table();  // BaseMotion's errors point here
  }
  read_loads(root, spec);

  // The model's own checks name the body (or the base); point at the table
  // that defined it.
  try {
    job.definition = define_model(spec);
    derive_model(job.definition, job.definition.parameters.nominal(), job.model);
  } catch (const ModelError& e) {
    const auto it = bodies.where.find(e.subject());
    if (it != bodies.where.end()) throw JobError(file, line_of(*it->second), column_of(*it->second), "", e.what());
    throw JobError(file, 0, 0, "", e.what());
  }
  job.initial = std::move(bodies.initial);

  if (auto integrator = root.subtable("integrator")) {
    read_integrator(*integrator, job.request);
    // Only the L^T D L solver has a depth limit (its blocks grow like the
    // sum of the depths); it is only ever chosen here, by name.
    if (resolve_solver(job.request.solver) == AccelerationSolver::sparse_ldlt) {
      try {
        require_sparse_factor_fits(*job.definition.topology);
      } catch (const ModelError& e) {
        integrator->fail("solver", e.what());
      }
    }
  }
  require_finite_start(job, bodies.where, file);
  const auto output = root.subtable("output");
  if (!output) throw JobError(file, 0, 0, "output", "missing [output] section: give end_time and step (or times)");
  job.output = read_output(*output, spec, job.request);
  return job;
}

Job read_job(const std::filesystem::path& path) { return read_job(JobDocument::read(path)); }

Job parse_job(std::string_view text, const std::string& file) {
  return read_job(JobDocument::parse(std::string(text), file));
}

}  // namespace treedyn
