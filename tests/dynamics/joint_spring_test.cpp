// The two joint spring laws (dynamics/joint_spring.cpp), each against an
// independent computation:
//
//  * closed forms for an isotropic spring turned by an angle phi about an
//    axis n: the quaternion law has V = k (1 - cos phi) and moment
//    -k sin(phi) n, the rotation-vector law V = k phi^2 / 2 and moment
//    -k phi n (MuJoCo's ball-joint law);
//  * for anisotropic K and random deviations: the moment is minus the
//    gradient of the law's energy, taken by central differences of an energy
//    written here from its definition (V = 2 e^T K e from the quaternion of
//    the deviation; V = theta^T K theta / 2 from its angle and axis);
//  * what each law does at 180 degrees, damping, and that only the relative
//    rotation matters.
#include "dynamics/joint_spring.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "support/random_tree.hpp"

namespace treedyn {
namespace {

constexpr double kPi = std::numbers::pi;

Mat3 rotation(double angle, const Vec3& axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

// The energies from their definitions, for a deviation D (child -> reference).
double quaternion_energy(const Mat3& K, const Mat3& D) {
  const Eigen::AngleAxisd aa(D);
  const Vec3 e = std::sin(aa.angle() / 2.0) * aa.axis();  // sign irrelevant: V is even in e
  return 2.0 * e.dot(K * e);
}

double rotation_vector_energy(const Mat3& K, const Mat3& D) {
  const Eigen::AngleAxisd aa(D);  // angle in [0, pi]
  const Vec3 theta = aa.angle() * aa.axis();
  return 0.5 * theta.dot(K * theta);
}

JointSpring spring(const Mat3& K, SpringLaw law) {
  JointSpring s;
  s.stiffness = K;
  s.law = law;
  return s;
}

Mat3 random_spd(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) = u(rng);
  return a * a.transpose() + 0.5 * Mat3::Identity();
}

// Isotropic spring, joint on the base, the child turned by phi about n:
// closed forms to 1e-13 (a few roundings of unit-size numbers).
TEST(JointSpring, IsotropicClosedForms) {
  const double k = 7.0;
  const Vec3 n = Vec3(1.0, -2.0, 0.5).normalized();
  for (double phi : {1e-6, 0.01, 0.3, 1.0, 2.0, 3.0}) {
    const Mat3 A = rotation(phi, n);
    const JointLoad q = joint_spring_load(spring(k * Mat3::Identity(), SpringLaw::quaternion), Mat3::Identity(), A,
                                          Vec3::Zero(), Vec3::Zero());
    EXPECT_NEAR(q.energy, k * (1.0 - std::cos(phi)), 1e-13) << phi;
    EXPECT_LT((q.moment - (-k * std::sin(phi) * n)).norm(), 1e-13) << phi;
    const JointLoad r = joint_spring_load(spring(k * Mat3::Identity(), SpringLaw::rotation_vector), Mat3::Identity(), A,
                                          Vec3::Zero(), Vec3::Zero());
    EXPECT_NEAR(r.energy, 0.5 * k * phi * phi, 1e-13) << phi;
    EXPECT_LT((r.moment - (-k * phi * n)).norm(), 1e-13) << phi;
  }
}

// Anisotropic K, random reference and deviations (angles up to 170 degrees):
// the moment on the child, in its frame, is -dV/d(delta) for a small
// rotation delta of the child in its own frame (D -> D exp([delta]x)),
// taken by central differences of the energies above with h = 1e-5.
// Truncation ~h^2 |V'''| ~ 1e-9; the check is to 1e-7 of |K|.
TEST(JointSpring, MomentIsMinusTheEnergyGradient) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(0.05, 170.0 * kPi / 180.0);
  for (SpringLaw law : {SpringLaw::quaternion, SpringLaw::rotation_vector}) {
    auto energy = law == SpringLaw::quaternion ? quaternion_energy : rotation_vector_energy;
    for (int trial = 0; trial < 50; ++trial) {
      const Mat3 K = random_spd(rng);
      JointSpring s = spring(K, law);
      s.reference = Quat(testing::random_rotation(rng));
      const Mat3 R_ref = s.reference.toRotationMatrix();
      const Mat3 A_parent = testing::random_rotation(rng);
      const Mat3 D = rotation(angle(rng), testing::random_vector(rng, 1.0));
      const Mat3 A_child = A_parent * R_ref * D;  // so that R_ref^T A_p^T A_c = D
      const JointLoad load = joint_spring_load(s, A_parent, A_child, Vec3::Zero(), Vec3::Zero());
      const Vec3 moment_child = A_child.transpose() * load.moment;
      EXPECT_NEAR(load.energy, energy(K, D), 1e-12 * K.norm()) << name(law);
      const double h = 1e-5;
      for (int a = 0; a < 3; ++a) {
        const double dV =
            (energy(K, D * rotation(h, Vec3::Unit(a))) - energy(K, D * rotation(-h, Vec3::Unit(a)))) / (2.0 * h);
        EXPECT_NEAR(moment_child[a], -dV, 1e-7 * K.norm()) << name(law) << " trial " << trial << " axis " << a;
      }
    }
  }
}

// Below 1e-3 rad the rotation-vector law's coefficient c of theta x (theta x
// K theta) comes from its series; there the closed form
// c = 1/angle^2 - cot(angle/2) / (2 angle), evaluated in long double, must
// give the same moment. With anisotropic K the c term is ~angle^2/12 of the
// moment, so a wrong series would show at 1e-8 relative; the check is 1e-13.
TEST(JointSpring, RotationVectorSmallAngleSeriesMatchesTheClosedForm) {
  std::mt19937_64 rng(5);
  for (double angle : {1e-5, 1e-4, 5e-4, 9.9e-4}) {
    const Mat3 K = random_spd(rng);
    const Vec3 n = testing::random_vector(rng, 1.0).normalized();
    const JointLoad load = joint_spring_load(spring(K, SpringLaw::rotation_vector), Mat3::Identity(),
                                             rotation(angle, n), Vec3::Zero(), Vec3::Zero());
    const Mat3 A = rotation(angle, n);
    const Vec3 theta = angle * n;
    const long double a = angle;
    const long double c = 1.0L / (a * a) - 1.0L / (std::tan(a / 2.0L) * 2.0L * a);
    const Vec3 Kt = K * theta;
    const Vec3 expected = -(Kt - 0.5 * theta.cross(Kt) + static_cast<double>(c) * theta.cross(theta.cross(Kt)));
    EXPECT_LT((A.transpose() * load.moment - expected).norm(), 1e-13 * Kt.norm()) << angle;
    // And the c term is large enough here to matter at this tolerance.
    EXPECT_GT((static_cast<double>(c) * theta.cross(theta.cross(Kt))).norm(), 1e-12 * Kt.norm()) << angle;
  }
}

// At 180 degrees: the quaternion law's moment falls to zero (smooth); the
// rotation-vector law's moment has size k pi and reverses as the angle
// passes pi (theta jumps to -theta), while its energy stays continuous.
TEST(JointSpring, BehaviourAtHalfTurn) {
  const double k = 2.0;
  const Vec3 n = Vec3::UnitZ();
  const double below = kPi - 1e-6, above = kPi + 1e-6;
  const auto load = [&](SpringLaw law, double phi) {
    return joint_spring_load(spring(k * Mat3::Identity(), law), Mat3::Identity(), rotation(phi, n), Vec3::Zero(),
                             Vec3::Zero());
  };
  EXPECT_LT(load(SpringLaw::quaternion, below).moment.norm(), 1e-5);
  EXPECT_LT(load(SpringLaw::quaternion, above).moment.norm(), 1e-5);
  const Vec3 m_below = load(SpringLaw::rotation_vector, below).moment;
  const Vec3 m_above = load(SpringLaw::rotation_vector, above).moment;
  EXPECT_NEAR(m_below.z(), -k * below, 1e-9);
  EXPECT_NEAR(m_above.z(), +k * (2.0 * kPi - above), 1e-9);  // the shorter way back
  EXPECT_NEAR(load(SpringLaw::rotation_vector, below).energy, load(SpringLaw::rotation_vector, above).energy, 1e-5);
}

// The damper: -C w_rel with w_rel = A_c^T (w_c - w_p) in the child's frame,
// for both laws; and a common rotation of parent and child rotates the
// moment with it (only the relative rotation and velocity matter).
TEST(JointSpring, DampingAndFrameIndependence) {
  std::mt19937_64 rng(11);
  for (SpringLaw law : {SpringLaw::quaternion, SpringLaw::rotation_vector}) {
    JointSpring s = spring(Mat3::Zero(), law);
    s.damping = random_spd(rng);
    const Mat3 Ap = testing::random_rotation(rng), Ac = testing::random_rotation(rng);
    const Vec3 wp = testing::random_vector(rng, 2.0), wc = testing::random_vector(rng, 2.0);
    const JointLoad d = joint_spring_load(s, Ap, Ac, wp, wc);
    EXPECT_LT((d.moment - Ac * (-s.damping * (Ac.transpose() * (wc - wp)))).norm(), 1e-13);
    EXPECT_EQ(d.energy, 0.0);

    s.stiffness = random_spd(rng);
    const Mat3 R = testing::random_rotation(rng);
    const JointLoad a = joint_spring_load(s, Ap, Ac, wp, wc);
    const JointLoad b = joint_spring_load(s, R * Ap, R * Ac, R * wp, R * wc);
    EXPECT_LT((b.moment - R * a.moment).norm(), 1e-12) << name(law);
    EXPECT_NEAR(b.energy, a.energy, 1e-12) << name(law);
  }
}

}  // namespace
}  // namespace treedyn
