// An independent check of the forward dynamics: Newton-Euler for every body
// with the joint reaction forces as unknowns, all in one dense linear system
// built from the ModelSpec alone (user order, the spec's own fields; none of
// the Model's precomputed constants such as augmented_inertia, barycentre,
// branch_d or subtree_mass, and none of the solver's stages). Also: the dense
// mass matrix K is symmetric positive definite and equals the inverse of the
// Newton-Euler compliance dw'/dM; a dense LDLT solve of K w' = Q gives the
// tree-sparse factorisation's w'; and the hot path does not allocate.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <new>
#include <numbers>
#include <random>
#include <string>
#include <variant>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "dynamics/data.hpp"
#include "dynamics/pipeline.hpp"
#include "dynamics/recovered.hpp"
#include "integrate/tree_ode.hpp"
#include "model/model.hpp"
#include "support/allocation_counting.inc"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

// ---------------------------------------------------------------------------
// The oracle.
// ---------------------------------------------------------------------------

// Joint spring-damper moment, an independent implementation of the law
// documented for JointSpring in model_spec.hpp (dynamics/joint_spring.hpp is
// NOT used). It works with the rotation matrix instead of the quaternion:
// with D = R_ref^T A_p^T A_c the deviation of the child from its reference
// pose (child frame), and the identities q0 e = axial(D) / 2 and
// e e^T = (D + D^T - (tr D - 1) E) / 4 of the unit quaternion q = (q0, e) of D,
//     V = 2 e^T K e = tr(K D) - tr(K) (tr D - 1) / 2.
// A virtual rotation phi of the child (child frame), D -> D (E + [phi]x), and
// tr(N [phi]x) = -2 phi . axial(N) give dV/dphi = -2 axial(K D) + tr(K) axial(D),
// so the moment on the child (child frame) is
//     tau = 2 axial(K D) - tr(K) axial(D) - C A_c^T (w_c - w_p)
// (for K = k E: -k sin(angle) axis; zero at 180 degrees, no flip). Y = A_c tau
// on the child and -Y on the parent; by construction V depends only on the
// relative rotation, so the pair does no work under a common rotation.
Vec3 axial(const Mat3& m) { return 0.5 * Vec3(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1)); }

Vec3 oracle_spring_moment(const JointSpring& s, const Mat3& A_parent, const Mat3& A_child, const Vec3& w_parent,
                          const Vec3& w_child) {
  const Mat3 K = 0.5 * (s.stiffness + s.stiffness.transpose());
  const Mat3 C = 0.5 * (s.damping + s.damping.transpose());
  const Mat3 R_ref = s.reference.normalized().toRotationMatrix();
  const Mat3 D = R_ref.transpose() * A_parent.transpose() * A_child;
  Vec3 tau = 2.0 * axial(Mat3(K * D)) - K.trace() * axial(D);
  tau -= C * (A_child.transpose() * (w_child - w_parent));
  return A_child * tau;
}

// r0''(t) straight from the BaseMotionSpec formulas in base_motion.hpp.
Vec3 oracle_base_acceleration(const BaseMotionSpec& spec, double t) {
  if (std::holds_alternative<FixedBase>(spec)) return Vec3::Zero();
  if (const auto* c = std::get_if<ConstantAccelerationBase>(&spec)) return c->acceleration;
  if (const auto* h = std::get_if<HarmonicBase>(&spec)) {
    Vec3 a = Vec3::Zero();
    for (int axis = 0; axis < 3; ++axis)
      for (const Harmonic& term : h->axes[axis]) {
        const double omega = 2.0 * std::numbers::pi * term.frequency;
        a[axis] -= term.amplitude * omega * omega * std::sin(omega * t + term.phase);
      }
    return a;
  }
  // Tabulated: spline coefficients are not re-derived here (not generated below).
  return BaseMotion(spec).at(t).acceleration;
}

// Tree shape of a spec in the user's order, from names only.
struct SpecTree {
  std::vector<int> parent;                 // user index, -1 for the base
  std::vector<int> joint;                  // index in spec.joints of body u's inboard joint
  std::vector<std::vector<int>> children;  // user indices
};

SpecTree spec_tree(const ModelSpec& spec) {
  const int n = static_cast<int>(spec.bodies.size());
  std::map<std::string, int> index;
  for (int u = 0; u < n; ++u) index[spec.bodies[u].name] = u;
  SpecTree t;
  t.parent.assign(n, -2);
  t.joint.assign(n, -1);
  t.children.assign(n, {});
  for (int j = 0; j < static_cast<int>(spec.joints.size()); ++j) {
    const JointSpec& js = spec.joints[j];
    const int c = index.at(js.child);
    t.joint[c] = j;
    t.parent[c] = js.parent == kBaseName ? -1 : index.at(js.parent);
  }
  for (int u = 0; u < n; ++u)
    if (t.parent[u] >= 0) t.children[t.parent[u]].push_back(u);
  return t;
}

// The dense Newton-Euler system S x = rhs. Unknowns, 9 per body u (user order):
// x[9u..9u+2] = a_u (CoM acceleration), x[9u+3..] = alpha_u (angular
// acceleration), x[9u+6..] = X_u (reaction of u's inboard joint on u; -X_u on
// the parent). Rows, 9 per body:
//   Newton:     m a_u - X_u + sum_k X_k = F_u
//   Euler:      I_u alpha_u - [r_u]x X_u + sum_k [s_k]x X_k
//                 = M_u - w_u x I_u w_u + Y_u - sum_k Y_k
//   constraint: a_u - [r_u]x alpha_u - a_p + [s_u]x alpha_p
//                 = w_p x (w_p x s_u) - w_u x (w_u x r_u)      (a_p... -> r0'' for the base joint)
// with k over the children of u, r_u = A_u on_child (CoM -> inboard joint),
// s_k = A_u on_parent(k) (CoM of u -> joint of child k), I_u = A_u J_u A_u^T.
struct NewtonEulerSystem {
  Eigen::MatrixXd S;
  Eigen::VectorXd rhs;
};

NewtonEulerSystem newton_euler_system(const ModelSpec& spec, const SpecTree& tree, const std::vector<Mat3>& A,
                                      const std::vector<Vec3>& w, double t) {
  const int n = static_cast<int>(spec.bodies.size());
  std::map<std::string, int> index;
  for (int u = 0; u < n; ++u) index[spec.bodies[u].name] = u;

  // Loads through the CoM and about the CoM, and joint moments Y (by child).
  std::vector<Vec3> F(n), M(n), Y(n, Vec3::Zero());
  for (int u = 0; u < n; ++u) {
    F[u] = spec.bodies[u].mass * spec.gravity;
    M[u].setZero();
  }
  for (const PointForce& f : spec.forces) {
    const int u = index.at(f.body);
    F[u] += f.force;
    M[u] += (A[u] * f.point).cross(f.force);
  }
  for (const BodyMoment& m : spec.moments) M[index.at(m.body)] += m.moment;
  for (int u = 0; u < n; ++u) {
    const int p = tree.parent[u];
    const JointSpring& s = spec.joints[tree.joint[u]].spring;
    Y[u] = p < 0 ? oracle_spring_moment(s, Mat3::Identity(), A[u], Vec3::Zero(), w[u])
                 : oracle_spring_moment(s, A[p], A[u], w[p], w[u]);
  }
  const Vec3 r0dd = oracle_base_acceleration(spec.base_motion, t);

  NewtonEulerSystem sys;
  sys.S = Eigen::MatrixXd::Zero(9 * n, 9 * n);
  sys.rhs = Eigen::VectorXd::Zero(9 * n);
  auto S = [&](int row, int col) { return sys.S.block<3, 3>(row, col); };
  const Mat3 E = Mat3::Identity();
  for (int u = 0; u < n; ++u) {
    const int a = 9 * u, alpha = 9 * u + 3, x = 9 * u + 6;
    const int newton = 9 * u, euler = 9 * u + 3, constraint = 9 * u + 6;
    const JointSpec& js = spec.joints[tree.joint[u]];
    const Mat3 I = A[u] * spec.bodies[u].inertia * A[u].transpose();
    const Vec3 r = A[u] * js.on_child;

    S(newton, a) = spec.bodies[u].mass * E;
    S(newton, x) = -E;
    sys.rhs.segment<3>(newton) = F[u];

    S(euler, alpha) = I;
    S(euler, x) = -cross_matrix(r);
    Vec3 euler_rhs = M[u] - w[u].cross(I * w[u]) + Y[u];
    for (int k : tree.children[u]) {
      const Vec3 s_k = A[u] * spec.joints[tree.joint[k]].on_parent;
      S(newton, 9 * k + 6) += E;
      S(euler, 9 * k + 6) += cross_matrix(s_k);
      euler_rhs -= Y[k];
    }
    sys.rhs.segment<3>(euler) = euler_rhs;

    S(constraint, a) = E;
    S(constraint, alpha) = -cross_matrix(r);
    Vec3 c_rhs = -w[u].cross(w[u].cross(r));
    const int p = tree.parent[u];
    if (p < 0) {
      c_rhs += r0dd;
    } else {
      const Vec3 s = A[p] * js.on_parent;
      S(constraint, 9 * p) = -E;
      S(constraint, 9 * p + 3) = cross_matrix(s);
      c_rhs += w[p].cross(w[p].cross(s));
    }
    sys.rhs.segment<3>(constraint) = c_rhs;
  }
  return sys;
}

struct NewtonEulerSolution {
  std::vector<Vec3> com_acceleration;      // a_u, user order
  std::vector<Vec3> angular_acceleration;  // alpha_u
  std::vector<Vec3> joint_reaction;        // X_u on body u from its inboard joint
  double residual = 0.0;                   // |S x - rhs| / (|S| |x| + |rhs|)
  bool invertible = false;
};

NewtonEulerSolution newton_euler(const ModelSpec& spec, const std::vector<Mat3>& A, const std::vector<Vec3>& w,
                                 double t) {
  const SpecTree tree = spec_tree(spec);
  const NewtonEulerSystem sys = newton_euler_system(spec, tree, A, w, t);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(sys.S);
  const Eigen::VectorXd x = lu.solve(sys.rhs);
  const int n = static_cast<int>(spec.bodies.size());
  NewtonEulerSolution out;
  out.invertible = lu.isInvertible();
  out.residual = (sys.S * x - sys.rhs).norm() / (sys.S.norm() * x.norm() + sys.rhs.norm());
  for (int u = 0; u < n; ++u) {
    out.com_acceleration.push_back(x.segment<3>(9 * u));
    out.angular_acceleration.push_back(x.segment<3>(9 * u + 3));
    out.joint_reaction.push_back(x.segment<3>(9 * u + 6));
  }
  return out;
}

// K from the oracle, in the Model's regular order: Q_i contains the applied
// moment M_i with coefficient +1 (59) and nothing else depends on it, so
// dw'/dM = K^-1. Its columns are the Newton-Euler responses to unit moments
// (the homogeneous system with one unit moment on the right).
Eigen::MatrixXd oracle_mass_matrix(const ModelSpec& spec, const Model& model, const std::vector<Mat3>& A_user) {
  const int n = static_cast<int>(spec.bodies.size());
  const SpecTree tree = spec_tree(spec);
  const std::vector<Vec3> w(n, Vec3::Zero());
  const NewtonEulerSystem sys = newton_euler_system(spec, tree, A_user, w, 0.0);
  Eigen::MatrixXd unit_moments = Eigen::MatrixXd::Zero(9 * n, 3 * n);
  for (int i = 0; i < n; ++i)  // column block i: unit moments on regular body i
    unit_moments.block<3, 3>(9 * model.tree().user_index[i] + 3, 3 * i) = Mat3::Identity();
  const Eigen::MatrixXd response = Eigen::FullPivLU<Eigen::MatrixXd>(sys.S).solve(unit_moments);
  Eigen::MatrixXd compliance(3 * n, 3 * n);
  for (int i = 0; i < n; ++i)
    compliance.middleRows<3>(3 * i) = response.middleRows<3>(9 * model.tree().user_index[i] + 3);
  return compliance.inverse();
}

// ---------------------------------------------------------------------------
// Random scenarios.
// ---------------------------------------------------------------------------

enum class BaseKind { fixed, harmonic, constant_acceleration, tabulated };

Mat3 random_spd(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  const Vec3 ev(u(rng), u(rng), u(rng));
  const Mat3 R = testing::random_rotation(rng);
  return R * ev.asDiagonal() * R.transpose();
}

struct ScenarioOptions {
  int bodies = 3;
  bool chain = false;
  bool star = false;
  bool springs = false;  // springs / dampers / references on some joints
  bool loads = false;    // point forces and moments on some bodies
  BaseKind base = BaseKind::fixed;
  SpringLaw law = SpringLaw::quaternion;  // of every spring
};

ModelSpec random_scenario(std::mt19937_64& rng, const ScenarioOptions& o) {
  testing::RandomTreeOptions tree;
  tree.bodies = o.bodies;
  tree.chain = o.chain;
  tree.star = o.star;
  tree.shuffle_order = true;
  ModelSpec spec = testing::random_tree(rng, tree);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Joints listed in yet another order than the bodies.
  std::shuffle(spec.joints.begin(), spec.joints.end(), rng);
  if (unit(rng) < 0.3) spec.gravity = testing::random_vector(rng, 12.0);

  if (o.springs) {
    for (JointSpec& j : spec.joints) {
      const double pick = unit(rng);
      if (pick < 0.25) continue;  // some joints stay free
      if (pick < 0.5)
        j.spring.stiffness = (2.0 + 20.0 * unit(rng)) * Mat3::Identity();
      else if (pick < 0.85)
        j.spring.stiffness = random_spd(rng, 1.0, 30.0);  // anisotropic
      if (unit(rng) < 0.6) j.spring.damping = random_spd(rng, 0.1, 3.0);
      if (unit(rng) < 0.5) j.spring.reference = Quat(testing::random_rotation(rng));
      j.spring.law = o.law;
    }
  }
  if (o.loads) {
    const int n = o.bodies;
    std::uniform_int_distribution<int> body(0, n - 1), count(1, 4);
    const int forces = count(rng), moments = count(rng);
    for (int k = 0; k < forces; ++k)
      spec.forces.push_back(
          {spec.bodies[body(rng)].name, testing::random_vector(rng, 0.5), testing::random_vector(rng, 20.0)});
    for (int k = 0; k < moments; ++k)
      spec.moments.push_back({spec.bodies[body(rng)].name, testing::random_vector(rng, 5.0)});
  }
  switch (o.base) {
    case BaseKind::fixed:
      spec.base_motion = FixedBase{testing::random_vector(rng, 1.0)};
      break;
    case BaseKind::harmonic: {
      HarmonicBase h;
      h.offset = testing::random_vector(rng, 1.0);
      std::uniform_int_distribution<int> terms(0, 2);
      for (int axis = 0; axis < 3; ++axis) {
        const int m = terms(rng);
        for (int k = 0; k < m; ++k)
          h.axes[axis].push_back({0.01 + 0.2 * unit(rng), 0.2 + 3.0 * unit(rng), 2.0 * std::numbers::pi * unit(rng)});
      }
      spec.base_motion = h;
      break;
    }
    case BaseKind::constant_acceleration:
      spec.base_motion = ConstantAccelerationBase{testing::random_vector(rng, 1.0), testing::random_vector(rng, 2.0),
                                                  testing::random_vector(rng, 8.0)};
      break;
    case BaseKind::tabulated: {  // not used by the oracle comparisons
      TabulatedBase tab;
      for (int k = 0; k <= 20; ++k) {
        tab.times.push_back(0.1 * k);
        tab.positions.push_back(testing::random_vector(rng, 0.3));
      }
      spec.base_motion = tab;
      break;
    }
  }
  return spec;
}

// Copies a user-order state into data in the regular order.
constexpr AccelerationSolver kBothSolvers[] = {AccelerationSolver::recursive, AccelerationSolver::sparse_ldlt};

void set_state(const Model& model, const InitialState& s, double t, Data& data) {
  data.time = t;
  for (int i = 0; i < model.n; ++i) {
    data.rotation[i] = s.rotation[model.tree().user_index[i]];
    data.angular_velocity[i] = s.angular_velocity[model.tree().user_index[i]];
  }
}

double stacked_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double& scale) {
  double diff = 0.0;
  scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff += (a[i] - b[i]).squaredNorm();
    scale += b[i].squaredNorm();
  }
  scale = std::sqrt(scale);
  return std::sqrt(diff);
}

// ---------------------------------------------------------------------------
// 1-2. The solver's w' and joint reactions against the Newton-Euler oracle.
// ---------------------------------------------------------------------------

// Tolerance 1e-10 (relative, norm of the stacked difference over the norm of
// the stacked oracle values). Both sides are double-precision solves of
// well-posed linear systems: the tree-sparse LDL^T of K (3n unknowns) and a
// full-pivot LU of the 9n-unknown Newton-Euler system (mixed units, but
// rank-revealing pivoting). For these trees (masses 0.5-2 kg, arms 0.1-0.6 m,
// n <= 12) cond(K) is measured at ~2e2 at worst (printed by the mass-matrix
// test; allow ~1e4 for unluckier draws), so each side is accurate to
// ~cond * eps ~ 1e-14 .. 1e-12 (measured worst ~1e-14); 1e-10 keeps a margin of
// >= 100 while still catching any sign or missing term (mutating the oracle's
// spring sign, base acceleration, point-force arm or spring frame convention
// gives errors of order 1).
TEST(NewtonEuler, AngularAccelerationsAndReactionsMatchOracle) {
  std::mt19937_64 rng(20260214);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double spins[] = {0.5, 3.0, 15.0};
  double worst_alpha = 0.0, worst_reaction = 0.0, worst_com = 0.0, worst_residual = 0.0;
  std::string worst_alpha_case, worst_reaction_case;
  int cases = 0;
  for (int n = 1; n <= 12; ++n) {
    for (int shape = 0; shape < (n > 2 ? 2 : 1); ++shape) {
      for (int variant = 0; variant < 12; ++variant) {
        ScenarioOptions o;
        o.bodies = n;
        o.chain = shape == 0;
        o.springs = (variant & 1) != 0;
        o.loads = (variant & 2) != 0;
        o.base = static_cast<BaseKind>(variant / 4);
        const ModelSpec spec = random_scenario(rng, o);
        const Model model = build_model(spec);
        for (int rep = 0; rep < 3; ++rep) {
          const InitialState state = testing::random_state(rng, n, spins[rep]);
          const double t = 5.0 * unit(rng);
          const NewtonEulerSolution ne = newton_euler(spec, state.rotation, state.angular_velocity, t);
          ASSERT_TRUE(ne.invertible);
          worst_residual = std::max(worst_residual, ne.residual);
          for (const AccelerationSolver solver : kBothSolvers) {
            Data data(model, solver);
            set_state(model, state, t, data);
            ASSERT_TRUE(forward_dynamics(model, data));
            const Recovered rec = recover(model, data);

            // Solver's w' straight from data, mapped to the user order.
            std::vector<Vec3> alpha(n);
            for (int i = 0; i < n; ++i) alpha[model.tree().user_index[i]] = data.angular_acceleration.segment<3>(3 * i);
            for (int u = 0; u < n; ++u)  // recover() must report the same w' (a copy)
              ASSERT_EQ((alpha[u] - rec.angular_acceleration[u]).norm(), 0.0);

            double scale = 0.0;
            const double alpha_err = stacked_difference(alpha, ne.angular_acceleration, scale) / scale;
            const double reaction_err = stacked_difference(rec.joint_reaction, ne.joint_reaction, scale) / scale;
            const double com_err = stacked_difference(rec.com_acceleration, ne.com_acceleration, scale) / scale;

            const std::string label = std::string(name(solver)) + " n=" + std::to_string(n) +
                                      (o.chain ? " chain" : " branched") + " variant=" + std::to_string(variant) +
                                      " rep=" + std::to_string(rep);
            EXPECT_LT(alpha_err, 1e-10) << label;
            EXPECT_LT(reaction_err, 1e-10) << label;
            EXPECT_LT(com_err, 1e-10) << label;
            if (alpha_err > worst_alpha) {
              worst_alpha = alpha_err;
              worst_alpha_case = label;
            }
            if (reaction_err > worst_reaction) {
              worst_reaction = reaction_err;
              worst_reaction_case = label;
            }
            worst_com = std::max(worst_com, com_err);
            ++cases;
          }
        }
      }
    }
  }
  std::printf("Newton-Euler oracle, %d cases:\n", cases);
  std::printf("  worst relative error w'        %.2e  (%s)\n", worst_alpha, worst_alpha_case.c_str());
  std::printf("  worst relative error X (joint) %.2e  (%s)\n", worst_reaction, worst_reaction_case.c_str());
  std::printf("  worst relative error r''       %.2e\n", worst_com);
  std::printf("  worst oracle LU residual       %.2e\n", worst_residual);
}

// The spring law alone, where a wrong convention could otherwise hide behind a
// small spring moment: the solver's Y (recover().joint_moment) against the
// independent matrix-form implementation above. Tolerance 1e-12 relative:
// both are a few dozen flops on O(1) numbers, no linear solve involved.
TEST(NewtonEuler, JointSpringMomentMatchesIndependentLaw) {
  std::mt19937_64 rng(77);
  double worst = 0.0;
  for (int n = 1; n <= 8; ++n) {
    ScenarioOptions o;
    o.bodies = n;
    o.springs = true;
    const ModelSpec spec = random_scenario(rng, o);
    const Model model = build_model(spec);
    const SpecTree tree = spec_tree(spec);
    Data data(model);
    for (int rep = 0; rep < 5; ++rep) {
      const InitialState s = testing::random_state(rng, n, 4.0);
      set_state(model, s, 0.0, data);
      ASSERT_TRUE(forward_dynamics(model, data));
      const Recovered rec = recover(model, data);
      for (int u = 0; u < n; ++u) {
        const int p = tree.parent[u];
        const JointSpring& js = spec.joints[tree.joint[u]].spring;
        const Vec3 Y =
            p < 0
                ? oracle_spring_moment(js, Mat3::Identity(), s.rotation[u], Vec3::Zero(), s.angular_velocity[u])
                : oracle_spring_moment(js, s.rotation[p], s.rotation[u], s.angular_velocity[p], s.angular_velocity[u]);
        // Free joints: both exactly zero; otherwise |Y| is O(1) N m.
        const double err = (rec.joint_moment[u] - Y).norm() / std::max(Y.norm(), 1e-6);
        EXPECT_LT(err, 1e-12) << "n=" << n << " body " << u << " solver " << rec.joint_moment[u].transpose()
                              << " oracle " << Y.transpose();
        worst = std::max(worst, err);
      }
    }
  }
  std::printf("joint spring-damper moment: worst relative error %.2e\n", worst);
}

// ---------------------------------------------------------------------------
// 3. The dense mass matrix.
// ---------------------------------------------------------------------------

// K is assembled block-symmetric by construction, so symmetry is checked to
// 1e-14 (rounding only). Positive definiteness: LLT succeeds and the smallest
// eigenvalue is positive. Dense LDLT vs the tree-sparse L^T D L: the same K
// and Q, two factorisation orders; each is backward stable, so the forward
// error is ~cond(K) eps; cond(K) is ~2e2 at worst here (printed), giving
// ~5e-14, so the tolerance is 1e-12 relative (measured worst ~3e-15; it would
// need cond(K) ~ 5e3 to reach it). K against the oracle's inverse compliance:
// a solve of the 9n NE system then an inversion of the 3n compliance, so
// ~cond^2 eps in the worst case; tolerance 1e-9 (measured worst ~5e-15).
TEST(NewtonEuler, DenseMassMatrixSymmetricPositiveDefiniteAndSolvesAlike) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_solve = 0.0, worst_oracle_k = 0.0, worst_cond = 0.0, worst_asym = 0.0;
  for (int n = 1; n <= 12; ++n) {
    for (int shape = 0; shape < 2; ++shape) {
      for (int rep = 0; rep < 4; ++rep) {
        ScenarioOptions o;
        o.bodies = n;
        o.chain = shape == 0;
        o.springs = rep % 2 == 1;
        o.loads = rep >= 2;
        o.base = static_cast<BaseKind>(rep % 3);
        const ModelSpec spec = random_scenario(rng, o);
        const Model model = build_model(spec);
        Data data(model, AccelerationSolver::sparse_ldlt);  // K needs its position stage
        const InitialState state = testing::random_state(rng, n, 3.0);
        set_state(model, state, 3.0 * unit(rng), data);
        ASSERT_TRUE(forward_dynamics(model, data));
        const Eigen::MatrixXd K = dense_mass_matrix(model, data);
        ASSERT_EQ(K.rows(), 3 * n);
        const std::string label =
            "n=" + std::to_string(n) + (o.chain ? " chain" : " branched") + " rep=" + std::to_string(rep);

        const double asym = (K - K.transpose()).cwiseAbs().maxCoeff() / K.cwiseAbs().maxCoeff();
        EXPECT_LT(asym, 1e-14) << label;
        worst_asym = std::max(worst_asym, asym);

        const Eigen::LLT<Eigen::MatrixXd> llt(K);
        EXPECT_EQ(llt.info(), Eigen::Success) << label;
        const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
        EXPECT_GT(ev[0], 0.0) << label;
        const double cond = ev[ev.size() - 1] / ev[0];
        worst_cond = std::max(worst_cond, cond);

        const Eigen::VectorXd w_dense = K.ldlt().solve(data.generalised_force);
        const double solve_err = (w_dense - data.angular_acceleration).norm() / w_dense.norm();
        EXPECT_LT(solve_err, 1e-12) << label << " cond(K) " << cond;
        worst_solve = std::max(worst_solve, solve_err);

        const Eigen::MatrixXd K_oracle = oracle_mass_matrix(spec, model, state.rotation);
        const double k_err = (K - K_oracle).norm() / K.norm();
        EXPECT_LT(k_err, 1e-9) << label << " cond(K) " << cond;
        worst_oracle_k = std::max(worst_oracle_k, k_err);
      }
    }
  }
  std::printf("mass matrix: worst asymmetry %.2e, worst cond(K) %.2e\n", worst_asym, worst_cond);
  std::printf("  dense LDLT vs tree-sparse w': worst relative error %.2e\n", worst_solve);
  std::printf("  K vs Newton-Euler (dw'/dM)^-1: worst relative error %.2e\n", worst_oracle_k);
}

// ---------------------------------------------------------------------------
// 3b. The recursive solver (section 8) against the L^T D L of K, a dense
// solve of K and the Newton-Euler oracle, on trees up to 100 bodies.
// ---------------------------------------------------------------------------

// Tolerance 1e-11 relative (stacked norms) for w' and the reactions X. All
// four are backward-stable double-precision solves of the same well-posed
// problem, so they differ by ~cond * eps: cond(K) of these 100-body chains is
// ~1e3-1e4 (the heavy end of a long chain hardly moves the light end), which
// gives ~1e-12 at worst; 1e-11 leaves a margin and still catches any wrong or
// missing term (one of order 1). The recursive solver's own X_i (Phi a + phi)
// is checked too, against recover()'s sum of m r'' - F over each subtree.
TEST(NewtonEuler, RecursiveSolverMatchesLdltDenseAndOracleUpTo100Bodies) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_ldlt = 0.0, worst_dense = 0.0, worst_oracle = 0.0, worst_x = 0.0, worst_x_own = 0.0;
  std::string worst_case;
  int cases = 0;
  const char* shapes[] = {"chain", "star", "random tree"};
  for (int n : {1, 2, 3, 5, 8, 13, 21, 34, 55, 100}) {
    for (int shape = 0; shape < 3; ++shape) {
      for (int variant = 0; variant < 8; ++variant) {
        ScenarioOptions o;
        o.bodies = n;
        o.chain = shape == 0;
        o.star = shape == 1;
        o.springs = (variant & 1) != 0;
        o.loads = (variant & 2) != 0;
        o.base = static_cast<BaseKind>(variant / 2);  // every kind, tabulated included
        o.law = variant % 3 == 0 ? SpringLaw::rotation_vector : SpringLaw::quaternion;
        const ModelSpec spec = random_scenario(rng, o);
        const Model model = build_model(spec);
        Data recursive(model, AccelerationSolver::recursive);
        Data ldlt(model, AccelerationSolver::sparse_ldlt);
        const InitialState state = testing::random_state(rng, n, 3.0);
        const double t = 0.05 + 1.9 * unit(rng);  // inside the tabulated base's 0..2 s
        set_state(model, state, t, recursive);
        set_state(model, state, t, ldlt);
        ASSERT_TRUE(forward_dynamics(model, recursive));
        ASSERT_TRUE(forward_dynamics(model, ldlt));
        const std::string label =
            "n=" + std::to_string(n) + " " + shapes[shape] + " variant=" + std::to_string(variant);
        SCOPED_TRACE(label);

        const Eigen::VectorXd& w_rec = recursive.angular_acceleration;
        const double ldlt_err = (w_rec - ldlt.angular_acceleration).norm() / ldlt.angular_acceleration.norm();
        const Eigen::VectorXd w_dense = dense_mass_matrix(model, ldlt).ldlt().solve(ldlt.generalised_force);
        const double dense_err = (w_rec - w_dense).norm() / w_dense.norm();
        EXPECT_LT(ldlt_err, 1e-11);
        EXPECT_LT(dense_err, 1e-11);

        const Recovered rec_r = recover(model, recursive);
        const Recovered rec_l = recover(model, ldlt);
        double scale = 0.0;
        const double x_err = stacked_difference(rec_r.joint_reaction, rec_l.joint_reaction, scale) / scale;
        EXPECT_LT(x_err, 1e-11);
        std::vector<Vec3> own_x(n);  // the recursion's X_i, user order
        for (int i = 0; i < n; ++i) own_x[model.tree().user_index[i]] = recursive.articulated.joint_reaction[i];
        const double x_own_err = stacked_difference(own_x, rec_r.joint_reaction, scale) / scale;
        EXPECT_LT(x_own_err, 1e-11);

        // The oracle has no tabulated base and only the quaternion spring law;
        // its 9n x 9n full-pivot LU costs ~(9n)^3, so above 30 bodies it runs
        // on one variant in four.
        const bool oracle_models_it = o.base != BaseKind::tabulated && (!o.springs || o.law == SpringLaw::quaternion);
        if (oracle_models_it && (n <= 30 || variant % 4 == 0)) {
          const NewtonEulerSolution ne = newton_euler(spec, state.rotation, state.angular_velocity, t);
          ASSERT_TRUE(ne.invertible);
          std::vector<Vec3> alpha(n);
          for (int i = 0; i < n; ++i) alpha[model.tree().user_index[i]] = w_rec.segment<3>(3 * i);
          const double oracle_err = stacked_difference(alpha, ne.angular_acceleration, scale) / scale;
          const double oracle_x_err = stacked_difference(own_x, ne.joint_reaction, scale) / scale;
          EXPECT_LT(oracle_err, 1e-11);
          EXPECT_LT(oracle_x_err, 1e-11);
          worst_oracle = std::max({worst_oracle, oracle_err, oracle_x_err});
        }
        if (std::max(ldlt_err, dense_err) > std::max(worst_ldlt, worst_dense)) worst_case = label;
        worst_ldlt = std::max(worst_ldlt, ldlt_err);
        worst_dense = std::max(worst_dense, dense_err);
        worst_x = std::max(worst_x, x_err);
        worst_x_own = std::max(worst_x_own, x_own_err);
        ++cases;
      }
    }
  }
  std::printf("recursive solver, %d cases up to 100 bodies:\n", cases);
  std::printf("  w' vs tree-sparse L^T D L   %.2e  (%s)\n", worst_ldlt, worst_case.c_str());
  std::printf("  w' vs dense LDLT of K       %.2e\n", worst_dense);
  std::printf("  X (recover) vs L^T D L      %.2e\n", worst_x);
  std::printf("  own X vs recover()          %.2e\n", worst_x_own);
  std::printf("  w' and X vs Newton-Euler    %.2e\n", worst_oracle);
}

// ---------------------------------------------------------------------------
// 4. No heap allocation in the hot path.
// ---------------------------------------------------------------------------

TEST(NewtonEuler, HotPathDoesNotAllocate) {
  // The counters must see both kinds of allocation, or the test is vacuous.
  {
    const AllocationCount before;
    auto* v = new std::vector<int>(16);
    delete v;
    const AllocationCount after;
    EXPECT_GT(after.news, before.news) << "operator new replacement not active";
  }
#if defined(TREEDYN_COUNTS_MALLOC)
  {
    const AllocationCount before;
    Eigen::VectorXd x = Eigen::VectorXd::Random(64);
    const AllocationCount after;
    EXPECT_GT(after.mallocs, before.mallocs) << "malloc interposition not active (Eigen)";
    EXPECT_NE(x.sum(), 12345.0);
  }
#else
  std::printf("note: malloc not interposed here; Eigen's allocations are not counted\n");
#endif

  std::mt19937_64 rng(99);
  const Parameterisation charts[] = {Parameterisation::euler313, Parameterisation::bryant123,
                                     Parameterisation::quaternion, Parameterisation::direction_cosines};
  for (int n : {1, 2, 7, 12}) {
    for (int shape = 0; shape < 4; ++shape) {
      const AccelerationSolver solver = kBothSolvers[shape / 2];
      SCOPED_TRACE(std::string(name(solver)));
      ScenarioOptions o;
      o.bodies = n;
      o.chain = shape % 2 == 0;
      o.springs = true;
      o.loads = true;
      // Every base motion and both spring laws go through the hot path.
      o.base = n == 12 ? BaseKind::tabulated : o.chain ? BaseKind::harmonic : BaseKind::constant_acceleration;
      o.law = n % 2 == 0 ? SpringLaw::rotation_vector : SpringLaw::quaternion;
      const ModelSpec spec = random_scenario(rng, o);
      const Model model = build_model(spec);
      Data data(model, solver);
      std::vector<InitialState> states;
      for (int k = 0; k < 4; ++k) states.push_back(testing::random_state(rng, n, 3.0));

      set_state(model, states[0], 0.1, data);
      ASSERT_TRUE(forward_dynamics(model, data));
      for (int k = 1; k < 4; ++k) {
        const AllocationCount before;
        set_state(model, states[k], 0.1 + 0.37 * k, data);  // assignments into sized vectors
        const bool ok = forward_dynamics(model, data);
        const AllocationCount after;
        ASSERT_TRUE(ok);
        EXPECT_EQ(after.news - before.news, 0) << "forward_dynamics, n=" << n << " state " << k;
        EXPECT_EQ(after.mallocs - before.mallocs, 0) << "forward_dynamics, n=" << n << " state " << k;
      }

      for (Parameterisation p : charts) {
        TreeOde ode(model, p, solver);
        std::vector<double> y(ode.size()), y_dot(ode.size());
        ode.pack(states[0], y);
        ASSERT_TRUE(ode.rhs(0.2, y, y_dot));
        std::vector<std::vector<double>> next;
        for (int k = 1; k < 4; ++k) {
          std::vector<double> yk = y;
          std::uniform_real_distribution<double> nudge(-0.05, 0.05);
          for (double& v : yk) v += nudge(rng);
          next.push_back(std::move(yk));
        }
        for (std::size_t k = 0; k < next.size(); ++k) {
          const AllocationCount before;
          const bool ok = ode.rhs(0.2 + 0.3 * static_cast<double>(k + 1), next[k], y_dot);
          const AllocationCount after;
          ASSERT_TRUE(ok);
          EXPECT_EQ(after.news - before.news, 0) << "TreeOde::rhs, " << name(p) << ", n=" << n << " call " << k;
          EXPECT_EQ(after.mallocs - before.mallocs, 0) << "TreeOde::rhs, " << name(p) << ", n=" << n << " call " << k;
        }
      }
    }
  }
}

}  // namespace
}  // namespace treedyn
