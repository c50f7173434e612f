// The recorder's row: every quantity of the catalogue writes exactly its
// columns, at its place in the row (output/quantities.hpp, recorder.hpp).
// On a random tree whose bodies are listed out of the regular order (so
// user and regular indices differ), with springs and two output points:
//  * the row holds the same bits as the Recovered members each column is
//    read from (==, the same operations on the same numbers). The base is
//    fixed, so its nine columns are zeros here: their places are checked by
//    the count alone;
//  * each extract alone, into a row of NaN sentinels, writes its count
//    exactly and says where it ended; the recorder refuses a quantity that
//    says otherwise, and a model of another number of bodies.
#include "output/recorder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

struct Recording {
  Model model;
  OutputSpec output;
  std::vector<Recovered> states;  // recover(everything) at each output time
  std::vector<double> values;     // the recorder's rows
  ColumnLayout layout;
};

Recording record_everything(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  testing::RandomTreeOptions options;
  options.bodies = 4;
  options.spring_stiffness = 2.0;
  options.spring_damping = 0.1;
  Recording r{build_model(testing::random_tree(rng, options)), {}, {}, {}, {}};
  for (const QuantityInfo& q : quantity_catalogue()) r.output.quantities.emplace_back(q.name);
  r.output.points = {{"a", "", Vec3(0.1, -0.2, 0.3), 2}, {"b", "", Vec3(-0.4, 0.0, 0.05), 0}};
  Recorder recorder(r.model, r.output);
  SimulationRequest request;
  request.accelerations_at_outputs = recorder.needs_accelerations();
  for (int k = 0; k <= 10; ++k) request.output_times.push_back(0.05 * k);
  const IntegrationOutcome outcome = simulate(r.model, testing::random_state(rng, options.bodies, 2.0), request,
                                              [&](const Model& m, const Data& data) {
                                                recorder.record(m, data);
                                                r.states.emplace_back();
                                                recover(m, data, r.states.back(), kRecoverEverything);
                                              });
  EXPECT_TRUE(outcome.ok()) << outcome.message;
  r.values = recorder.values();
  r.layout = recorder.layout();
  return r;
}

// Quantity q's values at output time k, as the recovered state gives them.
std::vector<double> expected(const Recording& r, std::size_t k, const std::string& q) {
  const Recovered& s = r.states[k];
  std::vector<double> out;
  const auto vec = [&out](const Vec3& v) { out.insert(out.end(), {v.x(), v.y(), v.z()}); };
  const auto each = [&vec](const std::vector<Vec3>& vs) {
    for (const Vec3& v : vs) vec(v);
  };
  if (q == "orientation")
    for (const Mat3& A : s.rotation) {
      const Quat c = canonical_quaternion(A);
      out.insert(out.end(), {c.w(), c.x(), c.y(), c.z()});
    }
  if (q == "angular_velocity") each(s.angular_velocity);
  if (q == "angular_acceleration") each(s.angular_acceleration);
  if (q == "com_position") each(s.com_position);
  if (q == "com_velocity") each(s.com_velocity);
  if (q == "com_acceleration") each(s.com_acceleration);
  if (q == "com_offset")
    for (const Vec3& com : s.com_position) {
      const Vec3 d = com - s.base.position;
      out.insert(out.end(), {d.x(), d.y(), d.z(), std::hypot(d.x(), d.y())});
    }
  if (q == "joint_position") each(s.joint_position);
  if (q == "joint_reaction") each(s.joint_reaction);
  if (q == "joint_reaction_magnitude")
    for (const Vec3& f : s.joint_reaction) out.push_back(f.norm());
  if (q == "joint_angle") out = s.joint_angle;
  if (q == "joint_axis") each(s.joint_axis);
  if (q == "joint_moment") each(s.joint_moment);
  if (q == "energy") out = {s.energy.kinetic, s.energy.potential, s.energy.spring, s.energy.total()};
  if (q == "angular_momentum") vec(s.angular_momentum_about_base);
  if (q == "base") {
    vec(s.base.position);
    vec(s.base.velocity);
    vec(s.base.acceleration);
  }
  if (q == "point_position")
    for (const OutputPoint& p : r.output.points) vec(body_point_position(s, p.body_index, p.point));
  return out;
}

TEST(Recorder, EveryQuantityWritesItsOwnColumnsAndNothingElse) {
  const Recording r = record_everything(20261203);
  const std::size_t columns = r.layout.columns;
  ASSERT_EQ(r.layout.quantity.size(), quantity_catalogue().size());
  ASSERT_EQ(r.states.size(), 11u);
  ASSERT_EQ(r.values.size(), r.states.size() * columns);
  for (std::size_t k = 0; k < r.states.size(); ++k)
    for (std::size_t q = 0; q < r.layout.quantity.size(); ++q) {
      const std::vector<double> want = expected(r, k, r.layout.quantity[q]);
      ASSERT_EQ(want.size(), r.layout.names[q].size()) << r.layout.quantity[q] << ": the test's own count";
      for (std::size_t c = 0; c < want.size(); ++c)
        EXPECT_EQ(r.values[k * columns + r.layout.offset[q] + c], want[c])
            << r.layout.quantity[q] << " column " << r.layout.names[q][c] << " at output " << k;
    }
}

// Each extract alone, into a row of sentinels: it writes its column count
// exactly, every value finite, and nothing past its last column.
TEST(Recorder, EachExtractFillsExactlyItsColumns) {
  const Recording r = record_everything(7);
  const Recovered& s = r.states.back();
  for (const QuantityInfo& q : quantity_catalogue()) {
    const std::size_t n = q.columns(r.model, r.output).size();
    std::vector<double> row(n + 8, std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(q.extract(s, r.output, row.data()), row.data() + n) << q.name << ": the end it returns";
    for (std::size_t c = 0; c < n; ++c) EXPECT_TRUE(std::isfinite(row[c])) << q.name << " column " << c;
    for (std::size_t c = n; c < row.size(); ++c) EXPECT_TRUE(std::isnan(row[c])) << q.name << " wrote past its columns";
  }
}

TEST(Recorder, RefusesAModelOfAnotherNumberOfBodies) {
  std::mt19937_64 rng(11);
  testing::RandomTreeOptions three, four;
  three.bodies = 3;
  four.bodies = 4;
  const Model named_for = build_model(testing::random_tree(rng, three));
  const Model other = build_model(testing::random_tree(rng, four));
  const OutputSpec output{{"com_position", "joint_angle"}, {}};
  Recorder recorder(named_for, output);
  Data data(other, AccelerationSolver::recursive);
  try {
    recorder.record(other, data);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "recorder: a model of 4 bodies, the columns are for 3");
  }
  EXPECT_TRUE(recorder.empty()) << "nothing recorded";
}

}  // namespace
}  // namespace treedyn
