// treedyn's forward dynamics next to DART's (articulated-body algorithm,
// Skeleton::computeForwardDynamics) and MuJoCo's (mj_forward), in one run, on
// the same models and the same states (benchmark_models.hpp).
//
// For every model the three engines are given the same state (absolute
// orientations and angular velocities, converted to each engine's relative
// joint coordinates), their angular accelerations are compared (absolute,
// inertial frame), and then each is timed: CPU time of the calling thread per
// call, the process pinned to one core, the engines interleaved in rounds
// (the order rotating every round) and the median of the rounds reported. A
// call includes setting the state from the engine's own coordinates, so
// every engine recomputes its kinematics each time.
//
//   peer_benchmark [--rounds R] [--min-ms T] [--cpu C]
//   peer_benchmark --accuracy     accuracy per cost instead (see accuracy_table)
//
// Exit 1 when the engines disagree by more than 1e-8 relative.
#include <Eigen/Eigenvalues>
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <mujoco/mujoco.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "benchmark_models.hpp"
#include "dynamics/data.hpp"
#include "dynamics/pipeline.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"

namespace {

using namespace treedyn;
using bench::Shape;

constexpr double kGravity = -9.81;

double thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

// The engine-independent description: user order = make_tree's order, every
// parent before its children.
struct Tree {
  int n = 0;
  std::vector<int> parent;  // -1: the base
  std::vector<double> mass;
  std::vector<Mat3> inertia;           // central, body frame
  std::vector<Vec3> on_parent;         // joint from the parent's CoM, parent frame (0 for the root)
  std::vector<Vec3> on_child;          // joint from the body's CoM, body frame
  std::vector<Mat3> rotation;          // A_i, absolute
  std::vector<Vec3> angular_velocity;  // w_i, absolute
  // Relative joint coordinates: R_rel = A_p^T A_i, v = A_i^T (w_i - w_p).
  std::vector<Mat3> relative_rotation;
  std::vector<Vec3> relative_velocity;
};

Tree describe(const ModelSpec& spec, const InitialState& state) {
  Tree t;
  t.n = static_cast<int>(spec.bodies.size());
  for (int i = 0; i < t.n; ++i) {
    const JointSpec& j = spec.joints[i];
    t.parent.push_back(j.parent == kBaseName ? -1 : std::stoi(j.parent.substr(1)));
    t.mass.push_back(spec.bodies[i].mass);
    t.inertia.push_back(spec.bodies[i].inertia);
    t.on_parent.push_back(j.on_parent);
    t.on_child.push_back(j.on_child);
    t.rotation.push_back(state.rotation[i]);
    t.angular_velocity.push_back(state.angular_velocity[i]);
  }
  for (int i = 0; i < t.n; ++i) {
    const int p = t.parent[i];
    const Mat3 Ap = p < 0 ? Mat3::Identity() : t.rotation[p];
    const Vec3 wp = p < 0 ? Vec3::Zero() : t.angular_velocity[p];
    t.relative_rotation.push_back(Ap.transpose() * t.rotation[i]);
    t.relative_velocity.push_back(t.rotation[i].transpose() * (t.angular_velocity[i] - wp));
  }
  return t;
}

// w' stacked, absolute, user order.
using Accelerations = std::vector<Vec3>;

// ---------------------------------------------------------------------------
// treedyn

struct TreedynEngine {
  explicit TreedynEngine(const ModelSpec& spec, const Tree& t) : model(build_model(spec)), data(model) {
    for (int i = 0; i < model.n; ++i) {
      const int u = model.tree().user_index[i];
      rotation.push_back(t.rotation[u]);
      angular_velocity.push_back(t.angular_velocity[u]);
    }
  }
  void call() {
    for (int i = 0; i < model.n; ++i) {
      data.rotation[i] = rotation[i];
      data.angular_velocity[i] = angular_velocity[i];
    }
    if (!forward_dynamics(model, data)) throw std::runtime_error("treedyn: forward_dynamics failed");
  }
  Accelerations accelerations() const {
    Accelerations out(static_cast<std::size_t>(model.n));
    for (int i = 0; i < model.n; ++i) out[model.tree().user_index[i]] = data.angular_acceleration.segment<3>(3 * i);
    return out;
  }
  Model model;
  Data data;
  std::vector<Mat3> rotation;
  std::vector<Vec3> angular_velocity;
};

// ---------------------------------------------------------------------------
// DART: body frames at the CoM, one BallJoint per body. A BallJoint's
// positions are the rotation vector of R_rel and its velocities the relative
// angular velocity in the child's frame.

struct DartEngine {
  explicit DartEngine(const Tree& t) : skeleton(dart::dynamics::Skeleton::create("tree")) {
    using namespace dart::dynamics;
    for (int i = 0; i < t.n; ++i) {
      BallJoint::Properties joint;
      joint.mName = "j" + std::to_string(i);
      joint.mT_ParentBodyToJoint = Eigen::Isometry3d::Identity();
      joint.mT_ParentBodyToJoint.translation() = t.on_parent[i];
      joint.mT_ChildBodyToJoint = Eigen::Isometry3d::Identity();
      joint.mT_ChildBodyToJoint.translation() = t.on_child[i];
      BodyNode::Properties body;
      body.mName = "b" + std::to_string(i);
      body.mInertia = Inertia(t.mass[i], Eigen::Vector3d::Zero(), t.inertia[i]);
      BodyNode* parent = t.parent[i] < 0 ? nullptr : bodies[t.parent[i]];
      bodies.push_back(skeleton->createJointAndBodyNodePair<BallJoint>(parent, joint, body).second);
    }
    skeleton->setGravity(Eigen::Vector3d(0.0, 0.0, kGravity));
    positions.resize(3 * t.n);
    velocities.resize(3 * t.n);
    for (int i = 0; i < t.n; ++i) {
      // The generalised coordinates of body i's joint (its index in the skeleton).
      const auto k = static_cast<Eigen::Index>(bodies[i]->getParentJoint()->getIndexInSkeleton(0));
      positions.segment<3>(k) = BallJoint::convertToPositions(t.relative_rotation[i]);
      velocities.segment<3>(k) = t.relative_velocity[i];
    }
  }
  void call() {
    skeleton->setPositions(positions);
    skeleton->setVelocities(velocities);
    skeleton->computeForwardDynamics();
  }
  Accelerations accelerations() const {
    Accelerations out;
    for (auto* b : bodies) out.push_back(b->getAngularAcceleration());
    return out;
  }
  Accelerations velocities_seen() const {
    Accelerations out;
    for (auto* b : bodies) out.push_back(b->getAngularVelocity());
    return out;
  }
  dart::dynamics::SkeletonPtr skeleton;
  std::vector<dart::dynamics::BodyNode*> bodies;
  Eigen::VectorXd positions, velocities;
};

// ---------------------------------------------------------------------------
// MuJoCo: nested bodies with their frames at the CoM, a ball joint at the
// joint point; no geoms, no contacts. qpos of a ball is the quaternion of
// R_rel, qvel the relative angular velocity in the child's frame, qacc its
// derivative: w_i' = w_p' + w_p x w_i + A_i qacc_i.

// tinyxml2 refuses elements nested more than 100 deep, so every 40 levels the
// subtree goes into a file of its own, pulled in by <include> (MuJoCo splices
// the included file's elements in place).
using XmlFiles = std::vector<std::pair<std::string, std::string>>;  // name, text

XmlFiles mujoco_xml(const Tree& t, double rk4_step) {
  XmlFiles files;
  auto number = [](double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
  };
  auto triple = [&](const Vec3& v) { return number(v.x()) + " " + number(v.y()) + " " + number(v.z()); };
  std::function<std::string(int, int)> body = [&](int i, int depth) -> std::string {
    // Principal moments and axes from Eigen: MuJoCo's compiler diagonalises a
    // fullinertia only to ~1e-7 relative, which would dominate the comparison.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(t.inertia[i]);
    Mat3 R = eig.eigenvectors();
    if (R.determinant() < 0.0) R.col(2) *= -1.0;
    const Quat axes(R);
    std::string xml = "<body name='b" + std::to_string(i) + "' pos='" + triple(t.on_parent[i] - t.on_child[i]) +
                      "'><joint type='ball' pos='" + triple(t.on_child[i]) + "'/><inertial pos='0 0 0' mass='" +
                      number(t.mass[i]) + "' diaginertia='" + triple(eig.eigenvalues()) + "' quat='" +
                      number(axes.w()) + " " + triple(axes.vec()) + "'/>";
    std::string children;
    for (int k = 0; k < t.n; ++k)
      if (t.parent[k] == i) children += body(k, depth + 1);
    if (depth % 40 == 39 && !children.empty()) {
      const std::string name = "part" + std::to_string(files.size()) + ".xml";
      files.emplace_back(name, "<mujoco>" + children + "</mujoco>");
      children = "<include file='" + name + "'/>";
    }
    return xml + children + "</body>";
  };
  std::string world;
  for (int i = 0; i < t.n; ++i)
    if (t.parent[i] < 0) world += body(i, 0);
  files.emplace_back("tree.xml",
                     "<mujoco model='tree'><compiler inertiafromgeom='false' angle='radian'/>"
                     "<option gravity='0 0 " +
                         number(kGravity) + "'" +
                         (rk4_step > 0.0 ? " integrator='RK4' timestep='" + number(rk4_step) + "'" : "") +
                         "><flag contact='disable'/></option><worldbody>" + world + "</worldbody></mujoco>");
  return files;
}

struct MujocoEngine {
  // rk4_step > 0: the model integrates with MuJoCo's RK4 at that step.
  explicit MujocoEngine(const Tree& t, double rk4_step = 0.0) : tree(t) {
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    for (const auto& [name, xml] : mujoco_xml(t, rk4_step)) {
      if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(xml.size())) != 0)
        throw std::runtime_error("mujoco: VFS full");
      std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name.c_str())], xml.data(), xml.size());
    }
    char error[1000] = "";
    model = mj_loadXML("tree.xml", vfs.get(), error, sizeof error);
    mj_deleteVFS(vfs.get());
    if (model == nullptr) throw std::runtime_error(std::string("mujoco: ") + error);
    data = mj_makeData(model);
    qpos.resize(static_cast<std::size_t>(model->nq));
    qvel.resize(static_cast<std::size_t>(model->nv));
    for (int i = 0; i < t.n; ++i) {
      const int jnt = model->body_jntadr[body_id(i)];
      const Quat q(t.relative_rotation[i]);
      double* p = &qpos[static_cast<std::size_t>(model->jnt_qposadr[jnt])];
      p[0] = q.w();
      p[1] = q.x();
      p[2] = q.y();
      p[3] = q.z();
      Eigen::Map<Vec3> v(qvel.data() + model->jnt_dofadr[jnt]);
      v = t.relative_velocity[i];
    }
  }
  ~MujocoEngine() {
    mj_deleteData(data);
    mj_deleteModel(model);
  }
  MujocoEngine(const MujocoEngine&) = delete;
  MujocoEngine& operator=(const MujocoEngine&) = delete;

  int body_id(int i) const { return mj_name2id(model, mjOBJ_BODY, ("b" + std::to_string(i)).c_str()); }
  void call() {
    std::copy(qpos.begin(), qpos.end(), data->qpos);
    std::copy(qvel.begin(), qvel.end(), data->qvel);
    mj_forward(model, data);
  }
  Accelerations accelerations() const {
    Accelerations out(static_cast<std::size_t>(tree.n));
    for (int i = 0; i < tree.n; ++i) {  // parents first
      const int jnt = model->body_jntadr[body_id(i)];
      const Vec3 qacc = Eigen::Map<const Vec3>(data->qacc + model->jnt_dofadr[jnt]);
      const int p = tree.parent[i];
      const Vec3 wp = p < 0 ? Vec3::Zero() : tree.angular_velocity[p];
      const Vec3 wp_dot = p < 0 ? Vec3::Zero() : out[p];
      out[i] = wp_dot + wp.cross(tree.angular_velocity[i]) + tree.rotation[i] * qacc;
    }
    return out;
  }
  const Tree& tree;
  mjModel* model = nullptr;
  mjData* data = nullptr;
  std::vector<double> qpos, qvel;
};

// ---------------------------------------------------------------------------

double relative_difference(const Accelerations& a, const Accelerations& b) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff += (a[i] - b[i]).squaredNorm();
    scale += b[i].squaredNorm();
  }
  return std::sqrt(diff / scale);
}

// ns per call: enough calls to fill min_ms of CPU time.
double time_once(const std::function<void()>& call, double min_ms) {
  long calls = 0;
  const double start = thread_cpu_ns();
  double now = start;
  long batch = 1;
  while (now - start < min_ms * 1e6) {
    for (long k = 0; k < batch; ++k) call();
    calls += batch;
    batch *= 2;
    now = thread_cpu_ns();
  }
  return (now - start) / static_cast<double>(calls);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// ---------------------------------------------------------------------------
// Accuracy per cost: the 10-link chain over 10 s of swinging about its
// hanging equilibrium (found by letting a damped copy come to rest), with
// random angular velocities up to 0.6 rad/s: large enough to be nonlinear,
// small enough not to be chaotic, so that a reference can be trusted. The
// final orientations against a tight reference (treedyn, erk_verner with
// direction cosines at rtol = atol = 1e-14, checked against quaternions at
// the same setting); error = the largest rotation angle over the bodies.
// treedyn: every method with quaternions at several tolerances; MuJoCo: RK4
// (4th order, quaternion integration) at several fixed steps.

constexpr double kAccuracyEnd = 10.0;

// Through the quaternion (2 atan2(|v|, |w|)): accurate for small angles,
// where acos of the trace would floor at ~1e-8.
double angle_between(const Mat3& a, const Mat3& b) {
  const Quat q(Mat3(a.transpose() * b));
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

double worst_angle(const std::vector<Mat3>& a, const std::vector<Mat3>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, angle_between(a[i], b[i]));
  return worst;
}

struct TimedRun {
  std::vector<Mat3> rotation;  // user order, at kAccuracyEnd
  double cpu_ms = 0.0;
  long rhs = 0;
};

TimedRun treedyn_run(const Model& model, const InitialState& initial, Method method, Parameterisation p, double tol,
                     double end = kAccuracyEnd) {
  SimulationRequest request;
  request.output_times = {end};
  request.parameterisation = p;
  request.settings.method = method;
  request.settings.relative_tolerance = tol;
  request.settings.absolute_tolerance = tol;
  request.settings.max_steps = 100'000'000;
  TimedRun r;
  const double start = thread_cpu_ns();
  const IntegrationOutcome out = simulate(model, initial, request, [&](const Model& m, const Data& d) {
    r.rotation.assign(static_cast<std::size_t>(m.n), Mat3::Identity());
    for (int i = 0; i < m.n; ++i) r.rotation[m.tree().user_index[i]] = d.rotation[i];
  });
  r.cpu_ms = (thread_cpu_ns() - start) * 1e-6;
  r.rhs = out.stats.rhs_evaluations;
  if (!out.ok()) throw std::runtime_error("treedyn: " + out.message);
  return r;
}

TimedRun mujoco_run(const Tree& tree, double step) {
  MujocoEngine mj(tree, step);
  TimedRun r;
  const long steps = std::lround(kAccuracyEnd / step);
  const double start = thread_cpu_ns();
  std::copy(mj.qpos.begin(), mj.qpos.end(), mj.data->qpos);
  std::copy(mj.qvel.begin(), mj.qvel.end(), mj.data->qvel);
  for (long k = 0; k < steps; ++k) mj_step(mj.model, mj.data);
  mj_kinematics(mj.model, mj.data);
  r.cpu_ms = (thread_cpu_ns() - start) * 1e-6;
  r.rhs = 4 * steps;
  for (int i = 0; i < tree.n; ++i)
    r.rotation.push_back(
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(mj.data->xmat + 9 * mj.body_id(i)));
  return r;
}

void accuracy_table() {
  const int n = 10;
  const ModelSpec spec = bench::make_tree(n, bench::kChain);
  InitialState initial = bench::make_state(n);
  {
    ModelSpec damped = spec;
    for (JointSpec& j : damped.joints) j.spring.damping = 2.0 * Mat3::Identity();
    const TimedRun rest =
        treedyn_run(build_model(damped), initial, Method::cvode_adams, Parameterisation::quaternion, 1e-10, 60.0);
    initial.rotation = rest.rotation;
    for (Vec3& w : initial.angular_velocity) w *= 0.2;
  }
  const Model model = build_model(spec);
  const Tree tree = describe(spec, initial);
  const TimedRun reference =
      treedyn_run(model, initial, Method::erk_verner, Parameterisation::direction_cosines, 1e-14);
  const TimedRun check = treedyn_run(model, initial, Method::erk_verner, Parameterisation::quaternion, 1e-14);
  std::printf(
      "\naccuracy per cost: chain-10, 10 s; reference spread (quaternion vs direction cosines at 1e-14) "
      "%.1e rad\n\n| integrator | setting | final-orientation error (rad) | CPU (ms) | rhs evaluations |\n"
      "|---|---|---:|---:|---:|\n",
      worst_angle(check.rotation, reference.rotation));
  for (Method m : {Method::cvode_adams, Method::cvode_bdf, Method::erk_dormand_prince, Method::erk_verner}) {
    for (double tol : {1e-6, 1e-8, 1e-10, 1e-12}) {
      const TimedRun r = treedyn_run(model, initial, m, Parameterisation::quaternion, tol);
      std::printf("| treedyn %s | rtol = atol = %.0e | %.1e | %.1f | %ld |\n", std::string(name(m)).c_str(), tol,
                  worst_angle(r.rotation, reference.rotation), r.cpu_ms, r.rhs);
      std::fflush(stdout);
    }
  }
  for (double h : {4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4}) {
    const TimedRun r = mujoco_run(tree, h);
    std::printf("| MuJoCo RK4 | h = %.2e s | %.1e | %.1f | %ld |\n", h, worst_angle(r.rotation, reference.rotation),
                r.cpu_ms, r.rhs);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 7, cpu = 0;
  double min_ms = 30.0;
  bool accuracy = false;
  for (int a = 1; a < argc; a += 2) {
    const std::string key = argv[a];
    if (key == "--accuracy") {
      accuracy = true;
      --a;
    } else if (a + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", key.c_str());
      return 2;
    } else if (key == "--rounds")
      rounds = std::atoi(argv[a + 1]);
    else if (key == "--min-ms")
      min_ms = std::atof(argv[a + 1]);
    else if (key == "--cpu")
      cpu = std::atoi(argv[a + 1]);
    else {
      std::fprintf(stderr, "usage: peer_benchmark [--rounds R] [--min-ms T] [--cpu C] [--accuracy]\n");
      return 2;
    }
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (sched_setaffinity(0, sizeof set, &set) != 0)
    std::perror("sched_setaffinity (not pinned)");
  else
    std::printf("pinned to CPU %d; %d rounds of >= %.0f ms CPU per engine and model\n", cpu, rounds, min_ms);
  mju_user_warning = [](const char* msg) { std::fprintf(stderr, "mujoco warning: %s\n", msg); };
  if (accuracy) {
    accuracy_table();
    return 0;
  }

  struct Case {
    Shape shape;
    int n;
  };
  const Case cases[] = {{bench::kChain, 1},   {bench::kChain, 3},   {bench::kChain, 10},
                        {bench::kChain, 30},  {bench::kChain, 100}, {bench::kBinary, 3},
                        {bench::kBinary, 10}, {bench::kBinary, 30}, {bench::kBinary, 100}};
  std::printf(
      "\n| model | treedyn (ns) | DART (ns) | MuJoCo (ns) | treedyn / DART | treedyn / MuJoCo | "
      "w' vs DART | w' vs MuJoCo |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  double worst_diff = 0.0, chain10 = 0.0, chain100 = 0.0;
  for (const Case& c : cases) {
    const ModelSpec spec = bench::make_tree(c.n, c.shape);
    const Tree tree = describe(spec, bench::make_state(c.n));
    TreedynEngine td(spec, tree);
    DartEngine dart(tree);
    MujocoEngine mj(tree);
    td.call();
    dart.call();
    mj.call();
    const Accelerations reference = td.accelerations();
    // The conversion of the state is checked too: DART's own absolute w.
    const double w_diff = relative_difference(dart.velocities_seen(), tree.angular_velocity);
    const double dart_diff = relative_difference(dart.accelerations(), reference);
    const double mj_diff = relative_difference(mj.accelerations(), reference);
    const double diff = std::max({dart_diff, mj_diff, w_diff});
    worst_diff = std::max(worst_diff, diff);

    std::vector<double> t_td, t_dart, t_mj;
    std::vector<std::function<void()>> calls = {[&] { t_td.push_back(time_once([&] { td.call(); }, min_ms)); },
                                                [&] { t_dart.push_back(time_once([&] { dart.call(); }, min_ms)); },
                                                [&] { t_mj.push_back(time_once([&] { mj.call(); }, min_ms)); }};
    for (int r = 0; r < rounds; ++r)
      for (int k = 0; k < 3; ++k) calls[static_cast<std::size_t>((r + k) % 3)]();
    const double a = median(t_td), b = median(t_dart), m = median(t_mj);
    if (c.shape == bench::kChain && c.n == 10) chain10 = a;
    if (c.shape == bench::kChain && c.n == 100) chain100 = a;
    std::printf("| %s-%d | %.0f | %.0f | %.0f | %.2f | %.2f | %.1e | %.1e |\n", bench::shape_name(c.shape), c.n, a, b,
                m, a / b, a / m, dart_diff, mj_diff);
    std::fflush(stdout);
  }
  std::printf("\ntreedyn t(chain-100) / t(chain-10) = %.1f\n", chain100 / chain10);
  std::printf("worst relative difference of w' (DART and MuJoCo against treedyn): %.1e\n", worst_diff);
  if (!(worst_diff < 1e-8)) {
    std::fprintf(stderr, "the engines disagree: %.1e > 1e-8\n", worst_diff);
    return 1;
  }
  return 0;
}
