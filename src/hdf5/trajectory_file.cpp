#include "hdf5/trajectory_file.hpp"

#include <algorithm>

#include "output/final_state.hpp"
#include "output/motion.hpp"

namespace treedyn::h5 {

void write_column_units(hid_t dataset, const ColumnLayout& layout, std::size_t quantity) {
  std::vector<std::string> units;
  for (std::size_t c = 0; c < layout.names[quantity].size(); ++c) units.push_back(column_unit(layout, quantity, c));
  if (std::any_of(units.begin(), units.end(), [&](const std::string& u) { return u != units.front(); }))
    write_attribute(dataset, "column_units", units);
}

void write_quantity_datasets(hid_t group, const ColumnLayout& layout, std::size_t times, std::span<const double> values,
                             const std::string& time_path) {
  std::vector<double> block;
  for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
    const std::size_t cols = layout.names[q].size();
    block.clear();
    for (std::size_t k = 0; k < times; ++k) {
      const auto row = values.subspan(k * layout.columns + layout.offset[q], cols);
      block.insert(block.end(), row.begin(), row.end());
    }
    const QuantityInfo& info = *layout.info[q];
    Handle set = write_matrix(group, layout.quantity[q], block, times, cols);
    write_attribute(set.id(), "units", std::string(info.units));
    write_attribute(set.id(), "description",
                    std::string(info.description) + "; rows: output times (" + time_path +
                        "), columns: see the 'columns' attribute");
    write_attribute(set.id(), "columns", layout.names[q]);
    write_column_units(set.id(), layout, q);
  }
}

namespace {

// Where the integrator re-expressed an orientation in a fresh chart (angle
// sets near their singular set, quaternions and direction cosines that
// drifted): time and body of each change, and the count per body.
void write_chart_changes(hid_t root, const Job& job, const IntegrationOutcome& outcome) {
  Handle group = create_group(root, "chart_changes");
  write_attribute(group.id(), "description",
                  std::string("orientation chart changes, each at the end of an integration step "
                              "(the integrator restarts there from its own state)"));
  std::vector<double> times;
  std::vector<long long> body, count(static_cast<std::size_t>(job.model.n), 0);
  for (const ChartChange& c : outcome.chart_changes) {
    times.push_back(c.time);
    body.push_back(c.body);
    ++count[static_cast<std::size_t>(c.body)];
  }
  {
    Handle set = write_vector(group.id(), "time", times);
    write_attribute(set.id(), "units", std::string("s"));
    write_attribute(set.id(), "description", std::string("time of each change, in time order"));
  }
  {
    const hsize_t dims[1] = {body.size()};
    Handle set = write_array(group.id(), "body", H5T_NATIVE_LLONG, body.data(), dims);
    write_attribute(set.id(), "units", std::string("1"));
    write_attribute(set.id(), "description",
                    std::string("body of each change: 0-based index into the root attribute 'bodies'"));
  }
  {
    const hsize_t dims[1] = {count.size()};
    Handle set = write_array(group.id(), "count", H5T_NATIVE_LLONG, count.data(), dims);
    write_attribute(set.id(), "units", std::string("1"));
    write_attribute(set.id(), "description", std::string("number of changes per body, in the order of 'bodies'"));
  }
}

}  // namespace

namespace {

// The recorder's rows (com_position, orientation, joint_position: motion_output())
// as poses (T x 7n) and stick-figure points (T x 2n x 3).
void split_motion(const Recorder& motion, std::size_t n, std::vector<double>& pose, std::vector<double>& points) {
  const std::size_t T = motion.times().size(), C = motion.layout().columns;
  pose.assign(T * 7 * n, 0.0);
  points.assign(T * 6 * n, 0.0);
  for (std::size_t t = 0; t < T; ++t) {
    const double* com = motion.values().data() + t * C;
    const double* q = com + 3 * n;
    const double* joint = q + 4 * n;
    for (std::size_t u = 0; u < n; ++u) {
      double* pu = pose.data() + (t * n + u) * 7;
      double* xu = points.data() + (t * n + u) * 6;
      for (std::size_t k = 0; k < 3; ++k) {
        pu[k] = xu[3 + k] = com[3 * u + k];
        xu[k] = joint[3 * u + k];
      }
      for (std::size_t k = 0; k < 4; ++k) pu[3 + k] = q[4 * u + k];
    }
  }
}

// /motion's poses and stick-figure points at every output time.
void write_motion_poses(hid_t g, const MotionScene& scene, const Recorder& motion) {
  const std::size_t n = scene.body.size(), T = motion.times().size();
  std::vector<double> pose, points;
  split_motion(motion, n, pose, points);
  std::vector<std::string> pose_columns, point_names;
  for (const std::string& b : scene.body) {
    for (const char* c : {"x", "y", "z", "q0", "q1", "q2", "q3"}) pose_columns.push_back(b + "." + c);
    point_names.insert(point_names.end(), {b + ".joint", b + ".com"});
  }
  Handle set = write_matrix(g, "pose", pose, T, 7 * n);
  write_attribute(set.id(), "units", std::string("m, 1"));
  write_attribute(set.id(), "description",
                  std::string("per body its centre of mass (inertial frame) and its orientation quaternion "
                              "(q0 >= 0, body to inertial); rows: /time"));
  write_attribute(set.id(), "columns", pose_columns);
  const hsize_t point_dims[3] = {T, 2 * n, 3};
  set = write_array(g, "points", H5T_NATIVE_DOUBLE, points.data(), point_dims);
  write_attribute(set.id(), "units", std::string("m"));
  write_attribute(set.id(), "description",
                  std::string("the stick figure: per body its inboard joint point and its centre of mass "
                              "(point_names), inertial frame; time x point x (x, y, z)"));
  write_attribute(set.id(), "point_names", point_names);
}

}  // namespace

Handle write_motion_scene(hid_t root, const MotionScene& scene, const std::string& about) {
  const std::size_t n = scene.body.size();
  Handle g = create_group(root, "motion");
  write_attribute(g.id(), "description", about);
  write_attribute(g.id(), "bodies", scene.body);
  write_attribute(g.id(), "parents", std::span<const long long>(scene.parent));
  write_attribute(g.id(), "shapes", scene.shape);
  const hsize_t segment_dims[2] = {scene.segments.size(), 2};
  Handle set = write_array(g.id(), "segments", H5T_NATIVE_INT64, scene.segments.data(), segment_dims);
  write_attribute(set.id(), "description",
                  std::string("the stick figure's line segments, as pairs of 0-based point rows (per body u: "
                              "2u its inboard joint, 2u + 1 its centre of mass): each body's joint to its "
                              "centre of mass, each child's joint to its parent's centre of mass"));
  set = write_matrix(g.id(), "dimensions", scene.dimensions, n, 3);
  write_attribute(set.id(), "units", std::string("m"));
  write_attribute(set.id(), "description",
                  std::string("per body (attribute shapes): box edges along body x, y, z; cylinder (radius, "
                              "radius, length along body z); sphere (radius x 3); zero for an explicit inertia; "
                              "the description's nominal values"));
  set = write_matrix(g.id(), "com_to_joint", scene.com_to_joint, n, 3);
  write_attribute(set.id(), "units", std::string("m"));
  write_attribute(set.id(), "description",
                  std::string("per body the vector from its centre of mass to its inboard joint, body frame"));
  return g;
}

void write_trajectory(const std::filesystem::path& path, const Job& job, const Recorder& recorder,
                      const IntegrationOutcome& outcome, const RunProvenance& run, const TrajectoryMotion& motion,
                      const SampleOrigin* sample) {
  File file(path);
  const hid_t root = file.id();
  write_attribute(root, "software", std::string("treedyn ") + TREEDYN_VERSION);
  write_attribute(root, "job_file", job.file);
  write_attribute(root, "job_text", job.text);
  write_attribute(root, "title", job.title);
  write_attribute(root, "method", std::string(name(job.request.settings.method)));
  write_attribute(root, "parameterisation", std::string(name(job.request.parameterisation)));
  write_attribute(root, "solver", std::string(name(resolve_solver(job.request.solver))));
  write_attribute(root, "relative_tolerance", job.request.settings.relative_tolerance);
  write_attribute(root, "absolute_tolerance", job.request.settings.absolute_tolerance);
  for (const IntegratorStatField& f : kIntegratorStatFields)
    write_attribute(root, std::string(f.name), static_cast<long long>(outcome.stats.*f.member));
  std::vector<std::string> bodies;
  for (int u = 0; u < job.model.n; ++u) bodies.push_back(job.model.tree().user_body_name(u));
  write_attribute(root, "bodies", bodies);
  write_provenance(root, run);

  const std::vector<double>& t = recorder.times();
  {
    Handle time = write_vector(root, "time", t);
    write_attribute(time.id(), "units", std::string("s"));
    write_attribute(time.id(), "description", std::string("output times"));
    write_attribute(time.id(), "columns", std::vector<std::string>{"time"});
  }
  write_quantity_datasets(root, recorder.layout(), t.size(), recorder.values(), "/time");
  if (!recorder.empty() && outcome.ok()) {
    std::vector<double> final_state(kFinalStatePerBody * static_cast<std::size_t>(job.model.n));
    write_final_state(recorder.last(), final_state);
    Handle set = write_vector(root, "final_state", final_state);
    write_attribute(set.id(), "units", std::string("1, rad/s"));
    write_attribute(set.id(), "description",
                    std::string("state at the last output time: per body the orientation "
                                "quaternion (q0 >= 0) and the inertial angular velocity"));
    write_attribute(set.id(), "columns", final_state_columns(job.model.tree()));
  }
  write_chart_changes(root, job, outcome);
  write_motion_poses(write_motion_scene(root, motion.scene,
                                        "the bodies' shapes, poses and stick figure at every output time (/time), "
                                        "for viewers: treedyn report's 3-D view, ParaView through FILE.xmf")
                         .id(),
                     motion.scene, motion.recorder);
  if (sample) {
    Handle group = create_group(root, "sample");
    write_attribute(group.id(), "description",
                    std::string("this trajectory is one ensemble sample integrated alone "
                                "(treedyn-ensemble --sample)"));
    write_attribute(group.id(), "index", static_cast<long long>(sample->index));
    write_attribute(group.id(), "status", static_cast<long long>(sample->status));
    write_attribute(group.id(), "reason", sample->reason);
    write_attribute(group.id(), "time_reached", sample->time_reached);
    if (!sample->inputs.empty()) {
      Handle set = write_vector(group.id(), "inputs", sample->inputs);
      write_attribute(set.id(), "units", std::string("SI (per column: the 'column_units' attribute)"));
      write_attribute(set.id(), "description",
                      std::string("the sample's sampled inputs, as in the ensemble's /samples/inputs row"));
      write_attribute(set.id(), "columns", sample->input_names);
      write_attribute(set.id(), "column_units", sample->input_units);
    }
  }
  file.commit();
}

}  // namespace treedyn::h5
