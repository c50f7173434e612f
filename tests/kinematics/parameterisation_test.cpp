// The four orientation parameterisations of docs/wittenburg.md, section 5,
// and their charts: unit tests of kinematics/parameterisation.hpp, then whole
// runs showing that every parameterisation (with its chart changes)
// integrates the same motion.
#include "kinematics/parameterisation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

constexpr double kPi = std::numbers::pi;

constexpr std::array<Parameterisation, 4> kAll = {Parameterisation::euler313, Parameterisation::bryant123,
                                                  Parameterisation::quaternion, Parameterisation::direction_cosines};

bool is_angle_set(Parameterisation p) { return p == Parameterisation::euler313 || p == Parameterisation::bryant123; }

double max_abs(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

// The matrices printed in section 5, typed in from the page.
Mat3 theory_bryant(double a1, double a2, double a3) {
  const double c1 = std::cos(a1), s1 = std::sin(a1), c2 = std::cos(a2), s2 = std::sin(a2), c3 = std::cos(a3),
               s3 = std::sin(a3);
  Mat3 A;
  A << c2 * c3, -c2 * s3, s2,                                    //
      c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2,  //
      s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2;
  return A;
}

Mat3 theory_euler(double psi, double th, double phi) {
  const double cps = std::cos(psi), sps = std::sin(psi), cth = std::cos(th), sth = std::sin(th), cph = std::cos(phi),
               sph = std::sin(phi);
  Mat3 A;
  A << cps * cph - sps * cth * sph, -cps * sph - sps * cth * cph, sps * sth,  //
      sps * cph + cps * cth * sph, -sps * sph + cps * cth * cph, -cps * sth,  //
      sth * sph, sth * cph, cth;
  return A;
}

// Euler parameters (scalar first) -> rotation, the textbook formula
// A = (q0^2 - e.e) E + 2 e e^T + 2 q0 [e]x for a unit quaternion.
Mat3 theory_quaternion(const double* q) {
  const Vec3 e(q[1], q[2], q[3]);
  return (q[0] * q[0] - e.dot(e)) * Mat3::Identity() + 2.0 * e * e.transpose() + 2.0 * q[0] * cross_matrix(e);
}

// Coordinates of a generic, well-conditioned point of each chart.
std::vector<double> random_coordinates(Parameterisation p, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-kPi, kPi), middle(-1.2, 1.2);
  std::vector<double> q(static_cast<std::size_t>(coordinate_count(p)));
  switch (p) {
    case Parameterisation::bryant123:
      q = {angle(rng), middle(rng), angle(rng)};  // |a2| < 1.2: cos a2 > 0.36
      break;
    case Parameterisation::euler313:
      q = {angle(rng), 0.5 * kPi + middle(rng), angle(rng)};  // sin theta > 0.36
      break;
    case Parameterisation::quaternion: {
      const Quat u(testing::random_rotation(rng));
      q = {u.w(), u.x(), u.y(), u.z()};
      break;
    }
    case Parameterisation::direction_cosines: {
      const Mat3 A = testing::random_rotation(rng);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) q[static_cast<std::size_t>(3 * r + c)] = A(r, c);
      break;
    }
  }
  return q;
}

// ---------------------------------------------------------------------------
// Unit tests of the coordinate maps.

// Tolerance 1e-14: both sides are a handful of products of sines and cosines
// of the same angles, so they agree to a few ulps of entries of size <= 1.
TEST(Parameterisation, AngleSetsMatchTheoryMatrices) {
  std::mt19937_64 rng(515);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  double worst_b = 0.0, worst_e = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double q[3] = {angle(rng), angle(rng), angle(rng)};
    worst_b = std::max(
        worst_b, max_abs(rotation_from_coordinates(Parameterisation::bryant123, q) - theory_bryant(q[0], q[1], q[2])));
    worst_e = std::max(
        worst_e, max_abs(rotation_from_coordinates(Parameterisation::euler313, q) - theory_euler(q[0], q[1], q[2])));
  }
  std::printf("worst |R(q) - theory|: bryant %.2e  euler %.2e\n", worst_b, worst_e);
  EXPECT_LT(worst_b, 1e-14);
  EXPECT_LT(worst_e, 1e-14);
}

// Tolerance 1e-14 (rounding, as above). A quaternion off the unit sphere must
// give the rotation of its normalised self (the header's promise). A direction-
// cosine matrix with noise ~1e-7 in its entries (drift of A^T A ~3e-7) must
// come back orthonormal to O(drift^2) ~1e-13 (we ask 1e-12) and within
// O(noise) of the exact rotation (we ask 1e-6).
TEST(Parameterisation, QuaternionAndDirectionCosinesGiveRotations) {
  std::mt19937_64 rng(516);
  std::uniform_real_distribution<double> scale(0.5, 2.0);
  std::normal_distribution<double> normal;
  double worst_q = 0.0, worst_q_scaled = 0.0, worst_dcm = 0.0, worst_dcm_drift = 0.0, worst_dcm_moved = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const Quat u(testing::random_rotation(rng));
    double q[4] = {u.w(), u.x(), u.y(), u.z()};
    const Mat3 exact = theory_quaternion(q);
    worst_q = std::max(worst_q, max_abs(rotation_from_coordinates(Parameterisation::quaternion, q) - exact));
    // Drifted off the sphere, and the opposite sign: the same rotation.
    const double s = (k % 2 ? -1.0 : 1.0) * scale(rng);
    for (double& c : q) c *= s;
    worst_q_scaled =
        std::max(worst_q_scaled, max_abs(rotation_from_coordinates(Parameterisation::quaternion, q) - exact));

    double a[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[3 * r + c] = exact(r, c);
    worst_dcm = std::max(worst_dcm, max_abs(rotation_from_coordinates(Parameterisation::direction_cosines, a) - exact));
    for (double& c : a) c += 1e-7 * normal(rng);
    const Mat3 R = rotation_from_coordinates(Parameterisation::direction_cosines, a);
    worst_dcm_drift = std::max(worst_dcm_drift, max_abs(R.transpose() * R - Mat3::Identity()));
    worst_dcm_moved = std::max(worst_dcm_moved, max_abs(R - exact));
  }
  std::printf(
      "quaternion %.2e (off-sphere %.2e)  dcm %.2e  dcm after 1e-7 noise: orthonormality "
      "%.2e, moved %.2e\n",
      worst_q, worst_q_scaled, worst_dcm, worst_dcm_drift, worst_dcm_moved);
  EXPECT_LT(worst_q, 1e-14);
  EXPECT_LT(worst_q_scaled, 1e-14);
  EXPECT_LT(worst_dcm, 1e-14);
  EXPECT_LT(worst_dcm_drift, 1e-12);
  EXPECT_LT(worst_dcm_moved, 1e-6);
}

// Direction cosines anywhere inside their chart (chart_margin >= 0, i.e.
// drift d = max|X^T X - E| up to the re-projection limit): one
// Newton-Schulz step leaves R^T R - E = -(3/4) D^2 + O(d^3), at most 2.25 d^2
// entrywise (plus rounding, 1e-15); rotation_from_coordinates takes three,
// so it must stay within that one-step bound. Drifts from 1e-9 up to the chart
// edge are drawn (symmetric stretches X = U (E + S), the part the projection
// must remove). The worst value at the edge is printed: it is what a run may
// hand to the dynamics and to observers.
TEST(Parameterisation, DirectionCosinesProjectionInsideChart) {
  std::mt19937_64 rng(521);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> exponent(-9.0, -5.5);
  double worst_ratio = 0.0, worst_at_edge = 0.0, largest_drift = 0.0;
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const Mat3 U = testing::random_rotation(rng);
    Mat3 S;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) S(i, j) = normal(rng);
    S = 0.5 * (S + S.transpose());
    S *= 0.5 * std::pow(10.0, exponent(rng)) / max_abs(S);
    const Mat3 X = U * (Mat3::Identity() + S);
    double q[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q[3 * i + j] = X(i, j);
    if (chart_margin(Parameterisation::direction_cosines, q) < 0.0) continue;
    ++inside;
    const double d = max_abs(X.transpose() * X - Mat3::Identity());
    const Mat3 R = rotation_from_coordinates(Parameterisation::direction_cosines, q);
    const double o = max_abs(R.transpose() * R - Mat3::Identity());
    worst_ratio = std::max(worst_ratio, (o - 1e-15) / (d * d));
    if (d > largest_drift) largest_drift = d;
    if (d > 0.5 * largest_drift) worst_at_edge = std::max(worst_at_edge, o);
  }
  std::printf(
      "DCM inside chart (%d cases, drift up to %.2e): worst |R^T R - E| / drift^2 = %.3f; "
      "worst |R^T R - E| near the largest drift %.2e\n",
      inside, largest_drift, worst_ratio, worst_at_edge);
  ASSERT_GT(inside, 1000);
  EXPECT_LE(worst_ratio, 2.25);
}

// R(q)' = R(q) [w_body]x when q' = coordinate_rates(q, w_body). Checked by a
// central difference of R along q': step h = 1e-5 gives truncation error
// ~h^2 |R'''| / 6 (|q'| ~ 5, |R'''| <~ 1e3 near the chart edge: ~2e-8) and
// rounding ~1e-16 / h = 1e-11, so 1e-7 holds with margin, while any wrong
// sign or swapped term in (64)-(68) is an O(|w|) = O(1) error.
TEST(Parameterisation, CoordinateRatesMatchFiniteDifference) {
  std::mt19937_64 rng(517);
  const double h = 1e-5;
  for (Parameterisation p : kAll) {
    const int nq = coordinate_count(p);
    double worst = 0.0;
    for (int k = 0; k < 500; ++k) {
      const std::vector<double> q = random_coordinates(p, rng);
      const Vec3 w = testing::random_vector(rng, 3.0);
      std::vector<double> q_dot(static_cast<std::size_t>(nq)), qp(q), qm(q);
      coordinate_rates(p, q.data(), w, q_dot.data());
      for (int c = 0; c < nq; ++c) {
        qp[static_cast<std::size_t>(c)] += h * q_dot[static_cast<std::size_t>(c)];
        qm[static_cast<std::size_t>(c)] -= h * q_dot[static_cast<std::size_t>(c)];
      }
      const Mat3 R = rotation_from_coordinates(p, q.data());
      const Mat3 fd = (rotation_from_coordinates(p, qp.data()) - rotation_from_coordinates(p, qm.data())) / (2.0 * h);
      worst = std::max(worst, max_abs(fd - R * cross_matrix(w)) / std::max(1.0, w.norm()));
    }
    std::printf("%-18s worst |dR/dt - R [w]x| / |w| = %.2e\n", std::string(name(p)).c_str(), worst);
    EXPECT_LT(worst, 1e-7) << name(p);
  }
}

// The angle sets' rates near (not at) the singular set, where the 1/cos and
// 1/sin gains are large (distance eps = 0.05..0.3 rad, m = sin eps): the
// identity R' = R [w]x must still hold. Same central difference with h =
// 1e-7; the rates grow like |w|/m, so the truncation error h^2 |R'''| grows
// like |w|^3/m^3 and the error is compared after scaling by m^3 / |w|:
// tolerance 1e-6 (truncation ~h^2 |w|^2 = 1e-13, rounding ~1e-16/h x m^3
// < 1e-10), while a wrong term in the rates is O(1) even after scaling.
TEST(Parameterisation, AngleRatesNearSingularSet) {
  std::mt19937_64 rng(518);
  std::uniform_real_distribution<double> angle(-kPi, kPi), close(0.05, 0.3);
  const double h = 1e-7;
  for (Parameterisation p : {Parameterisation::bryant123, Parameterisation::euler313}) {
    double worst = 0.0;
    for (int k = 0; k < 500; ++k) {
      const double eps = close(rng);  // distance of the middle angle from the singular value
      const double sgn = k % 2 ? 1.0 : -1.0;
      double q[3] = {angle(rng), 0.0, angle(rng)};
      q[1] = p == Parameterisation::bryant123 ? sgn * (0.5 * kPi - eps) : (k % 4 < 2 ? eps : kPi - eps);
      const Vec3 w = testing::random_vector(rng, 3.0);
      double q_dot[3], qp[3], qm[3];
      coordinate_rates(p, q, w, q_dot);
      for (int c = 0; c < 3; ++c) {
        qp[c] = q[c] + h * q_dot[c];
        qm[c] = q[c] - h * q_dot[c];
      }
      const Mat3 fd = (rotation_from_coordinates(p, qp) - rotation_from_coordinates(p, qm)) / (2.0 * h);
      const Mat3 exact = rotation_from_coordinates(p, q) * cross_matrix(w);
      const double m = std::sin(eps);
      worst = std::max(worst, max_abs(fd - exact) * m * m * m / std::max(1.0, w.norm()));
    }
    std::printf("%-10s near singular set: worst scaled error %.2e\n", std::string(name(p)).c_str(), worst);
    EXPECT_LT(worst, 1e-6) << name(p);
  }
}

// recentre returns (C, q) with C R(q) = A to 1e-14 (a product of two or three
// exactly orthogonal matrices: rounding only); the new coordinates sit deep in
// their chart (angle sets: margin 0.75 at the centre; we ask > 0.5) or exactly
// normalised (quaternion/DCM: the drift margin is essentially at its maximum,
// i.e. the drift is below 1e-14); C is a rotation; C is the identity for
// quaternions and direction cosines.
TEST(Parameterisation, RecentreReproducesOrientation) {
  std::mt19937_64 rng(519);
  for (Parameterisation p : kAll) {
    double worst = 0.0, worst_c = 0.0, least_margin = 1e300, worst_drift = 0.0;
    // Random orientations, plus the singular orientations of the angle sets.
    std::vector<Mat3> cases;
    for (int k = 0; k < 300; ++k) cases.push_back(testing::random_rotation(rng));
    cases.push_back(Mat3::Identity());                                                // Euler theta = 0
    cases.push_back(Eigen::AngleAxisd(kPi, Vec3::UnitX()).toRotationMatrix());        // Euler theta = pi
    cases.push_back(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitY()).toRotationMatrix());  // Bryant a2 = 90
    cases.push_back(Eigen::AngleAxisd(-0.5 * kPi, Vec3::UnitY()).toRotationMatrix() *
                    Eigen::AngleAxisd(1.0, Vec3::UnitZ()).toRotationMatrix());  // Bryant a2 = -90
    for (const Mat3& A : cases) {
      std::vector<double> q = random_coordinates(p, rng);  // "the current ones" on entry
      const Mat3 C = recentre(p, A, q.data());
      const Mat3 R = rotation_from_coordinates(p, q.data());
      worst = std::max(worst, max_abs(C * R - A));
      worst_c = std::max(worst_c, max_abs(C.transpose() * C - Mat3::Identity()) + std::abs(C.determinant() - 1.0));
      least_margin = std::min(least_margin, chart_margin(p, q.data()));
      if (!is_angle_set(p)) {
        EXPECT_LT(max_abs(C - Mat3::Identity()), 1e-15) << name(p);
        // The raw coordinates themselves are (numerically) exact.
        double drift = 0.0;
        if (p == Parameterisation::quaternion) {
          drift = std::abs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0);
        } else {
          Mat3 D;
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) D(r, c) = q[static_cast<std::size_t>(3 * r + c)];
          drift = max_abs(D.transpose() * D - Mat3::Identity());
        }
        worst_drift = std::max(worst_drift, drift);
      }
    }
    std::printf("%-18s |C R(q) - A| %.2e  |C^T C - E| %.2e  least margin %.3g  coordinate drift %.2e\n",
                std::string(name(p)).c_str(), worst, worst_c, least_margin, worst_drift);
    EXPECT_LT(worst, 1e-14) << name(p);
    EXPECT_LT(worst_c, 1e-14) << name(p);
    EXPECT_GT(least_margin, 0.0) << name(p);
    if (is_angle_set(p)) {
      EXPECT_GT(least_margin, 0.5) << name(p);
    }
    EXPECT_LT(worst_drift, 1e-14) << name(p);
  }
}

// A quaternion and its negative are one rotation; recentre must keep the sign
// of the coordinates it is given (else the integrated q would jump by 2|q|).
// The incoming q is drifted (|q|^2 = 1 + 1e-8 .. 1e-6), as when the drift
// root fires. Tolerance 1e-14: after the sign choice, only normalisation.
TEST(Parameterisation, QuaternionRecentreKeepsSign) {
  std::mt19937_64 rng(520);
  std::uniform_real_distribution<double> drift(1e-8, 1e-6);
  for (int k = 0; k < 400; ++k) {
    const Quat u(testing::random_rotation(rng));
    const double s = (k % 2 ? -1.0 : 1.0) * std::sqrt(1.0 + drift(rng));
    double q[4] = {s * u.w(), s * u.x(), s * u.y(), s * u.z()};
    const double before[4] = {q[0], q[1], q[2], q[3]};
    const Mat3 A = rotation_from_coordinates(Parameterisation::quaternion, q);
    const Mat3 C = recentre(Parameterisation::quaternion, A, q);
    double dot = 0.0, diff = 0.0;
    for (int c = 0; c < 4; ++c) {
      dot += q[c] * before[c];
      diff = std::max(diff, std::abs(q[c] - before[c] / std::abs(s)));
    }
    ASSERT_GT(dot, 0.0) << "sign flipped, case " << k;
    EXPECT_LT(diff, 1e-14) << "case " << k;
    EXPECT_LT(max_abs(C * rotation_from_coordinates(Parameterisation::quaternion, q) - A), 1e-14);
  }
}

// ---------------------------------------------------------------------------
// Whole runs.

struct Trajectory {
  IntegrationOutcome outcome;
  std::vector<double> time;
  std::vector<std::vector<Mat3>> rotation;  // [output][user body]
  std::vector<std::vector<Vec3>> angular_velocity;
  std::vector<double> energy;
};

Trajectory run(const ModelSpec& spec, const InitialState& initial, Parameterisation p, const std::vector<double>& times,
               double rtol, double atol) {
  const Model model = build_model(spec);
  SimulationRequest request;
  request.parameterisation = p;
  request.settings.method = Method::cvode_adams;
  request.settings.relative_tolerance = rtol;
  request.settings.absolute_tolerance = atol;
  request.output_times = times;
  Trajectory out;
  out.outcome = simulate(model, initial, request, [&](const Model& m, const Data& data) {
    const Recovered r = recover(m, data);
    out.time.push_back(r.time);
    out.rotation.push_back(r.rotation);
    out.angular_velocity.push_back(r.angular_velocity);
    out.energy.push_back(r.energy.total());
  });
  return out;
}

std::vector<double> grid(double duration, int intervals) {
  std::vector<double> t;
  for (int k = 0; k <= intervals; ++k) t.push_back(duration * k / intervals);
  return t;
}

// The same tumbling tree integrated with each parameterisation must give the
// same orientations: the four are different coordinates for one ODE on SO(3),
// and the angle sets change chart several times on the way. Tolerance 1e-7
// rad: a wrong rate equation, a jump at a chart change or a chart base applied
// on the wrong side would be O(1).
// The bar is only meaningful if the motion is not so sensitive that the
// integration error (~1e-11 per unit time at rtol 1e-12) is amplified to 1e-7
// within 10 s: random 4-body trees at 3-6 rad/s amplify it by 1e3-1e5 (their
// quaternion runs at rtol 1e-12 and 1e-13 already differ by up to 5e-6 rad).
// So the tree here is a 3-body one with |w| up to 4.5 rad/s whose reference is
// checked to be converged: quaternion runs at rtol 1e-12 and 1e-13 agree to
// 1e-8 rad (measured ~1e-9), leaving the 1e-7 bar a margin of 10 or more.
TEST(ParameterisationRuns, AllFourAgreeOnTumblingTree) {
  std::mt19937_64 rng(1003);
  testing::RandomTreeOptions options;
  options.bodies = 3;
  const ModelSpec spec = testing::random_tree(rng, options);
  const InitialState initial = testing::random_state(rng, options.bodies, 8.0);
  const std::vector<double> times = grid(10.0, 400);
  auto worst_difference = [&](const Trajectory& a, const Trajectory& b, double* at = nullptr,
                              double* w_diff = nullptr) {
    double worst = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      for (std::size_t u = 0; u < static_cast<std::size_t>(options.bodies); ++u) {
        const double d = testing::rotation_distance(a.rotation[k][u], b.rotation[k][u]);
        if (d > worst) {
          worst = d;
          if (at) *at = times[k];
        }
        if (w_diff) *w_diff = std::max(*w_diff, (a.angular_velocity[k][u] - b.angular_velocity[k][u]).norm());
      }
    }
    return worst;
  };

  const Trajectory reference = run(spec, initial, Parameterisation::quaternion, times, 1e-12, 1e-12);
  const Trajectory tighter = run(spec, initial, Parameterisation::quaternion, times, 1e-13, 1e-13);
  ASSERT_TRUE(reference.outcome.ok()) << reference.outcome.message;
  ASSERT_TRUE(tighter.outcome.ok()) << tighter.outcome.message;
  ASSERT_EQ(reference.rotation.size(), times.size());
  ASSERT_EQ(tighter.rotation.size(), times.size());
  const double self = worst_difference(reference, tighter);
  std::printf("quaternion rtol 1e-12 vs 1e-13 (convergence of the reference): %.2e rad\n", self);
  ASSERT_LT(self, 1e-8) << "the reference motion is too sensitive for a 1e-7 comparison";

  for (Parameterisation p : kAll) {
    if (p == Parameterisation::quaternion) continue;
    const Trajectory other = run(spec, initial, p, times, 1e-12, 1e-12);
    ASSERT_TRUE(other.outcome.ok()) << name(p) << ": " << other.outcome.message;
    ASSERT_EQ(other.rotation.size(), times.size());
    double worst_time = 0.0, worst_w = 0.0;
    const double worst = worst_difference(reference, other, &worst_time, &worst_w);
    const auto& s = other.outcome.stats;
    std::printf(
        "%-18s vs quaternion: worst rotation difference %.2e rad (t = %.3f s), |w| difference "
        "%.2e rad/s, steps %ld, chart changes %ld, restarts %ld\n",
        std::string(name(p)).c_str(), worst, worst_time, worst_w, s.steps, s.chart_changes, s.restarts);
    EXPECT_LT(worst, 1e-7) << name(p);
    // |w| differences: same scale (the rates of the orientations), times |w'|/|w| ~ 10.
    EXPECT_LT(worst_w, 1e-6) << name(p);
    if (is_angle_set(p)) {
      EXPECT_GT(s.chart_changes, 0) << name(p) << " never changed chart";
    }
  }
}

// One body on the base, no gravity, inertia about the pivot isotropic
// (K = k E): a torque-free body about a fixed point with spherical K, so
// K w' = -w x K w = 0, w is constant and A(t) = exp(t [w]x) A0 exactly.
// Mass 1 kg, CoM 0.5 m below the joint along body z: m(|c|^2 E - c c^T) =
// diag(0.25, 0.25, 0), so J = diag(0.35, 0.35, 0.6) gives K = 0.6 E.
ModelSpec spherical_pendulum_body() {
  ModelSpec spec;
  BodySpec b;
  b.name = "top";
  b.mass = 1.0;
  b.inertia = Vec3(0.35, 0.35, 0.6).asDiagonal();
  spec.bodies.push_back(b);
  JointSpec j;
  j.parent = kBaseName;
  j.child = "top";
  j.on_child = Vec3(0.0, 0.0, 0.5);
  spec.joints.push_back(j);
  spec.gravity = Vec3::Zero();
  return spec;
}

// The motions are chosen to cross each angle set's singular orientation of its
// first chart: with A0 = E the Bryant chart starts at q = 0 (C = E), and
// rotation about y drives a2 through 90 degrees; the Euler chart starts at
// theta = 90 degrees with C = A0 Rx(pi/2)^T, and rotation about body x by -90
// degrees reaches theta = 0; a generic axis crosses both many times over.
// Charts change at step ends. Along the three axis-aligned motions the angles
// are exactly linear in time, so the integrator's steps grow by 10x at a time
// and may step straight across the singular set, accurately (the rates stay
// finite there for these motions); only the generic motion, whose rates do
// blow up at the singular set, must change charts.
// Tolerance 1e-8 rad on the orientation over 10 s (up to ~45 rad of rotation)
// at rtol = atol = 1e-12: the integration error is ~1e-10; a wrong chart base
// or a jump at a re-basing would show as an O(1) error.
TEST(ParameterisationRuns, SingularPassagesMatchClosedForm) {
  const ModelSpec spec = spherical_pendulum_body();
  struct Case {
    const char* what;
    Mat3 A0;
    Vec3 w;
    bool bryant_singular;  // the Bryant (resp. Euler) rates blow up on the way,
    bool euler_singular;   // so the chart must change
  };
  const Mat3 tilted = Eigen::AngleAxisd(0.7, Vec3(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const std::vector<Case> cases = {
      {"about y from E (Bryant a2 -> 90 deg)", Mat3::Identity(), Vec3(0.0, 3.0, 0.0), false, false},
      {"about -x from E (Euler theta -> 0)", Mat3::Identity(), Vec3(-3.0, 0.0, 0.0), false, false},
      {"about x from E (Euler theta -> 180)", Mat3::Identity(), Vec3(2.5, 0.0, 0.0), false, false},
      {"generic axis, tilted start", tilted, Vec3(1.3, -2.1, 2.7), true, true},
  };
  const std::vector<double> times = grid(10.0, 1000);
  for (const Case& c : cases) {
    InitialState initial;
    initial.rotation = {c.A0};
    initial.angular_velocity = {c.w};
    for (Parameterisation p : kAll) {
      const Trajectory r = run(spec, initial, p, times, 1e-12, 1e-12);
      ASSERT_TRUE(r.outcome.ok()) << c.what << ", " << name(p) << ": " << r.outcome.message;
      ASSERT_EQ(r.rotation.size(), times.size());
      double worst = 0.0, worst_w = 0.0;
      for (std::size_t k = 0; k < times.size(); ++k) {
        const Mat3 exact = Eigen::AngleAxisd(c.w.norm() * times[k], c.w.normalized()).toRotationMatrix() * c.A0;
        worst = std::max(worst, testing::rotation_distance(exact, r.rotation[k][0]));
        worst_w = std::max(worst_w, (r.angular_velocity[k][0] - c.w).norm());
      }
      std::printf("%-38s %-18s rotation error %.2e rad  |w - w0| %.2e  chart changes %ld  restarts %ld\n", c.what,
                  std::string(name(p)).c_str(), worst, worst_w, r.outcome.stats.chart_changes,
                  r.outcome.stats.restarts);
      EXPECT_LT(worst, 1e-8) << c.what << ", " << name(p);
      // w' = 0 exactly in the equations; only rounding in K w' = -w x K w.
      EXPECT_LT(worst_w, 1e-9) << c.what << ", " << name(p);
      if ((p == Parameterisation::bryant123 && c.bryant_singular) ||
          (p == Parameterisation::euler313 && c.euler_singular)) {
        EXPECT_GT(r.outcome.stats.chart_changes, 0) << c.what << ", " << name(p);
      }
    }
  }
}

// Long run at default tolerances (rtol 1e-8, atol 1e-10): 200 s of a heavy,
// asymmetric body tumbling on its pivot. Whatever the integrated coordinates
// do (quaternion norm and DCM orthonormality drift; angle sets re-based), the
// orientations handed out must be rotations: A^T A = E to 1e-12 and det A = 1
// (the solver normalises / re-orthonormalises before use, and re-projects the
// coordinates themselves when they drift). For direction cosines the one
// Newton-Schulz step leaves up to 2.25 drift^2 (see
// DirectionCosinesProjectionInsideChart), which stays below 1e-12 only while
// the drift stays below ~6.7e-7; measured here: ~4e-13. Energy is printed,
// and bounded loosely (1e-4 relative; measured 2e-7..3e-6) only to catch a
// gross failure such as a restart storm (re-projections every few steps when
// the local error per step is of the size of the drift limit).
TEST(ParameterisationRuns, LongRunKeepsRotationsOrthonormal) {
  std::mt19937_64 rng(777);
  testing::RandomTreeOptions options;
  options.bodies = 1;
  const ModelSpec spec = testing::random_tree(rng, options);
  InitialState initial;
  initial.rotation = {testing::random_rotation(rng)};
  initial.angular_velocity = {Vec3(3.0, -4.0, 5.0)};
  const std::vector<double> times = grid(200.0, 4000);
  const IntegratorSettings defaults;
  for (Parameterisation p : kAll) {
    const Trajectory r = run(spec, initial, p, times, defaults.relative_tolerance, defaults.absolute_tolerance);
    ASSERT_TRUE(r.outcome.ok()) << name(p) << ": " << r.outcome.message;
    ASSERT_EQ(r.rotation.size(), times.size());
    double worst = 0.0, worst_det = 0.0, worst_e = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const Mat3& A = r.rotation[k][0];
      worst = std::max(worst, max_abs(A.transpose() * A - Mat3::Identity()));
      worst_det = std::max(worst_det, std::abs(A.determinant() - 1.0));
      worst_e = std::max(worst_e, std::abs(r.energy[k] - r.energy[0]));
    }
    const auto& s = r.outcome.stats;
    std::printf(
        "%-18s |A^T A - E| %.2e  |det - 1| %.2e  energy drift %.2e J (E0 %.3f J)  steps %ld  "
        "chart changes %ld  restarts %ld\n",
        std::string(name(p)).c_str(), worst, worst_det, worst_e, r.energy[0], s.steps, s.chart_changes, s.restarts);
    EXPECT_LT(worst, 1e-12) << name(p);
    EXPECT_LT(worst_det, 1e-12) << name(p);
    EXPECT_LT(worst_e, 1e-4 * std::max(1.0, std::abs(r.energy[0]))) << name(p);
  }
}

}  // namespace
}  // namespace treedyn
