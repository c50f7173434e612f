// The shipped example jobs, run through the real `treedyn` command: each must
// run (exit 0), write a well-formed HDF5 file (read back with the HDF5 C API:
// /time, one (times x columns) dataset per quantity with units, description
// and column labels, the run's root attributes), and show the physics it was
// written to show (energy and momentum conservation, dissipation, Kapitza's
// stabilisation, the cable tension of the crane).
//
// Also: `treedyn check` on every example, `--version`, `run --help`.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/hdf5_reader.hpp"

namespace {

namespace fs = std::filesystem;

using namespace treedyn::testing;

using Matrix = DoubleArray;

// Runs `treedyn ARGS` with stdout and stderr captured into files in `dir`.
CommandResult run_treedyn(const std::vector<std::string>& args, const fs::path& dir) {
  return run_command(TREEDYN_BINARY, args, dir);
}

// ---------------------------------------------------------------------------
// The examples

struct Example {
  std::string name;  // jobs/<name>.toml
  double end_time, step;
  std::string method, parameterisation;
  std::vector<std::string> bodies;      // in file order ([[body]] first, then [[chain]])
  std::vector<std::string> points;      // [[output.point]] names
  std::vector<std::string> quantities;  // as requested; empty = the whole catalogue
};

const std::vector<std::string> kCatalogue = {"orientation",   "angular_velocity", "angular_acceleration",
                                             "com_position",  "com_velocity",     "com_acceleration",
                                             "com_offset",    "joint_position",   "joint_reaction",
                                             "joint_angle",   "joint_axis",       "joint_moment",
                                             "energy",        "angular_momentum", "base",
                                             "point_position"};

const Example& example(const std::string& name) {
  static const std::vector<Example> all = {
      {"spherical_pendulum", 10.0, 0.01, "cvode_adams", "quaternion", {"rod"}, {"tip"}, {}},
      {"double_pendulum", 10.0, 0.01, "cvode_adams", "quaternion", {"upper", "lower"}, {}, {}},
      {"chain10",
       3.0,
       0.005,
       "cvode_adams",
       "bryant123",
       {"link1", "link2", "link3", "link4", "link5", "link6", "link7", "link8", "link9", "link10"},
       {},
       {"orientation", "com_position", "joint_reaction", "energy", "angular_momentum"}},
      {"y_tree",
       5.0,
       0.01,
       "erk_verner",
       "quaternion",
       {"trunk", "left_arm", "right_arm", "left_hand", "right_hand"},
       {},
       {}},
      {"crane_payload",
       60.0,
       0.1,
       "cvode_adams",
       "quaternion",
       // Bodies in the job file's order: the [[chain]] stands before the container.
       {"cable1", "cable2", "cable3", "cable4", "container"},
       {"container_corner"},
       {"com_position", "com_offset", "orientation", "joint_reaction", "joint_reaction_magnitude", "joint_angle",
        "energy", "base", "point_position"}},
      {"kapitza",
       5.0,
       0.002,
       "cvode_adams",
       "quaternion",
       {"rod"},
       {},
       {"orientation", "angular_velocity", "com_position", "joint_angle", "energy", "base"}},
  };
  for (const Example& e : all)
    if (e.name == name) return e;
  throw std::invalid_argument("no example " + name);
}

fs::path job_path(const Example& e) { return fs::path(TREEDYN_JOBS_DIR) / (e.name + ".toml"); }

std::vector<std::string> expected_quantities(const Example& e) {
  if (!e.quantities.empty()) return e.quantities;
  std::vector<std::string> q;
  for (const auto& name : kCatalogue)
    if (name != "point_position" || !e.points.empty()) q.push_back(name);
  return q;
}

std::vector<std::string> expected_columns(const Example& e, const std::string& quantity) {
  auto per_body = [&](std::initializer_list<const char*> suffixes) {
    std::vector<std::string> out;
    for (const auto& b : e.bodies)
      for (const char* s : suffixes) out.push_back(b + "." + s);
    return out;
  };
  if (quantity == "orientation") return per_body({"q0", "q1", "q2", "q3"});
  if (quantity == "joint_angle") return per_body({"angle"});
  if (quantity == "joint_reaction_magnitude") return per_body({"magnitude"});
  if (quantity == "com_offset") return per_body({"x", "y", "z", "horizontal"});
  if (quantity == "energy") return {"kinetic", "potential", "spring", "total"};
  if (quantity == "angular_momentum") return {"x", "y", "z"};
  if (quantity == "base")
    return {"position.x", "position.y",     "position.z",     "velocity.x",    "velocity.y",
            "velocity.z", "acceleration.x", "acceleration.y", "acceleration.z"};
  if (quantity == "point_position") {
    std::vector<std::string> out;
    for (const auto& p : e.points)
      for (const char* s : {"x", "y", "z"}) out.push_back(p + "." + s);
    return out;
  }
  return per_body({"x", "y", "z"});
}

std::size_t column_index(hid_t file, const std::string& dataset, const std::string& column) {
  const auto columns = read_string_attribute(file, dataset, "columns");
  const auto it = std::find(columns.begin(), columns.end(), column);
  if (it == columns.end()) throw std::runtime_error(dataset + " has no column " + column);
  return static_cast<std::size_t>(it - columns.begin());
}

// Relative energy drift max |E - E0| / (|T0| + |V0| + S0) over the output.
double relative_energy_drift(const Matrix& energy) {
  const double scale = std::abs(energy(0, 0)) + std::abs(energy(0, 1)) + std::abs(energy(0, 2));
  double drift = 0.0;
  for (std::size_t r = 0; r < energy.rows(); ++r) drift = std::max(drift, std::abs(energy(r, 3) - energy(0, 3)));
  return drift / scale;
}

// Runs one example into a temp dir, checks the command and the file's
// structure, and keeps the file open for the physics checks.
class ExampleRun {
 public:
  explicit ExampleRun(const std::string& name) : example_(example(name)), dir_("examples_test") {
    output_ = dir_.path() / "x.h5";
    result_ = run_treedyn({"run", job_path(example_).string(), "-o", output_.string()}, dir_.path());
  }

  // Exit code, stdout, the file's layout and attributes. Returns false (after
  // reporting) when the file cannot be opened.
  bool check_structure() {
    EXPECT_EQ(result_.exit_code, 0) << "stdout:\n" << result_.out << "stderr:\n" << result_.err;
    EXPECT_EQ(result_.err, "");
    EXPECT_NE(result_.out.find("wrote " + output_.string()), std::string::npos) << result_.out;
    // Written atomically: the final file and nothing else (no x.h5.tmp-*).
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(dir_.path())) left.push_back(entry.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"x.h5"});

    file_.emplace(output_);  // reports a file it cannot open
    if (!file_->ok()) return false;

    // /time: 0, step, 2 step, ..., end_time.
    const auto expected_times = static_cast<std::size_t>(std::llround(example_.end_time / example_.step)) + 1;
    time_ = read_double_array(file(), "time");
    EXPECT_EQ(time_.dims, std::vector<hsize_t>{expected_times});
    if (time_.data.size() == expected_times) {
      EXPECT_EQ(time_.data.front(), 0.0);
      EXPECT_NEAR(time_.data.back(), example_.end_time, 1e-12 * example_.end_time);
      for (std::size_t k = 0; k < expected_times; ++k)
        EXPECT_NEAR(time_.data[k], static_cast<double>(k) * example_.step, 1e-9) << "k = " << k;
    }
    {
      Hid time(H5Dopen2(file(), "time", H5P_DEFAULT), H5Dclose);
      EXPECT_EQ(read_single_string_attribute(time.get(), "units"), "s");
    }

    // One (times x columns) dataset per quantity, with units, description, columns.
    for (const std::string& q : expected_quantities(example_)) {
      SCOPED_TRACE("quantity " + q);
      const auto expected = expected_columns(example_, q);
      const Matrix m = read_double_array(file(), q);
      EXPECT_EQ(m.dims, (std::vector<hsize_t>{expected_times, expected.size()}));
      for (double v : m.data) {
        if (!std::isfinite(v)) {
          ADD_FAILURE() << "non-finite value in " << q;
          break;
        }
      }
      Hid set(H5Dopen2(file(), q.c_str(), H5P_DEFAULT), H5Dclose);
      if (!set.ok()) continue;
      for (const char* a : {"units", "description", "columns"})
        EXPECT_TRUE(has_attribute(set.get(), a)) << "attribute " << a;
      EXPECT_FALSE(read_single_string_attribute(set.get(), "units").empty());
      EXPECT_FALSE(read_single_string_attribute(set.get(), "description").empty());
      EXPECT_EQ(read_string_attribute(set.get(), "columns"), expected);
    }
    // No quantity that was not asked for.
    for (const auto& q : kCatalogue) {
      const auto wanted = expected_quantities(example_);
      if (std::find(wanted.begin(), wanted.end(), q) == wanted.end()) {
        EXPECT_LE(H5Lexists(file(), q.c_str(), H5P_DEFAULT), 0) << "unrequested dataset " << q;
      }
    }

    // Root attributes.
    EXPECT_EQ(read_single_string_attribute(file(), "software"), std::string("treedyn ") + TREEDYN_VERSION);
    EXPECT_EQ(read_single_string_attribute(file(), "job_text"), read_text(job_path(example_)));
    EXPECT_EQ(read_single_string_attribute(file(), "method"), example_.method);
    EXPECT_EQ(read_single_string_attribute(file(), "parameterisation"), example_.parameterisation);
    EXPECT_EQ(read_string_attribute(file(), "bodies"), example_.bodies);
    steps_ = read_integer_attribute(file(), "steps");
    EXPECT_GT(steps_, 0);
    EXPECT_GT(read_integer_attribute(file(), "rhs_evaluations"), 0);
    EXPECT_EQ(read_single_string_attribute(file(), "solver"), "recursive");

    // The chart-change log adds up to the counter, per body and in all.
    const long long changes = read_integer_attribute(file(), "chart_changes");
    const std::vector<double> change_times = read_doubles(file(), "chart_changes/time");
    const std::vector<long long> change_body = read_integers(file(), "chart_changes/body");
    const std::vector<long long> per_body = read_integers(file(), "chart_changes/count");
    EXPECT_EQ(static_cast<long long>(change_times.size()), changes);
    EXPECT_EQ(change_body.size(), change_times.size());
    EXPECT_EQ(per_body.size(), example_.bodies.size());
    long long total = 0;
    for (long long c : per_body) total += c;
    EXPECT_EQ(total, changes);
    for (std::size_t k = 0; k < change_times.size(); ++k) {
      EXPECT_GE(change_body[k], 0);
      EXPECT_LT(change_body[k], static_cast<long long>(example_.bodies.size()));
      if (k > 0) {
        EXPECT_LE(change_times[k - 1], change_times[k]);
      }
    }
    std::printf("%s: %lld chart changes\n", example_.name.c_str(), changes);
    return true;
  }

  hid_t file() const { return file_ ? file_->id() : H5I_INVALID_HID; }
  const Matrix& time() const { return time_; }
  Matrix dataset(const std::string& name) const { return read_double_array(file(), name); }
  std::size_t column(const std::string& dataset, const std::string& label) const {
    return column_index(file(), dataset, label);
  }

 private:
  const Example& example_;
  TempDir dir_;
  fs::path output_;
  CommandResult result_;
  std::optional<H5File> file_;
  Matrix time_;
  long long steps_ = 0;
};

// The job file must still say what the table above assumes.
void expect_job_says(const std::string& name, std::initializer_list<const char*> lines) {
  const std::string text = read_text(job_path(example(name)));
  for (const char* line : lines)
    EXPECT_NE(text.find(line), std::string::npos) << name << ".toml no longer contains: " << line;
}

// ---------------------------------------------------------------------------
// Energy bounds. Each is ~10x the drift measured on the example (Release,
// x86-64, SUNDIALS CVODE Adams), i.e. a few times what the local tolerances
// allow: with rtol r the per-step relative error is ~r, and over the ~1e3-4e3
// steps of a run the energy error random-walks to ~r * sqrt(steps), not
// r * steps, because the error per step is not biased in sign.
//   spherical_pendulum: rtol 1e-10, 781 steps,  measured 4.6e-11 -> bound 5e-10
//   double_pendulum:    rtol 1e-10, 3448 steps, measured 2.0e-8  -> bound 2e-7
//                       (chaotic: errors grow with the Lyapunov exponent)
//   chain10:            rtol 1e-9,  4155 steps, measured 1.6e-9  -> bound 2e-8
// All are well below 1e-6, which a wrong sign or a missing term in the
// dynamics would exceed by orders of magnitude.

TEST(Examples, SphericalPendulumConservesEnergyAndVerticalAngularMomentum) {
  expect_job_says("spherical_pendulum", {"end_time = 10.0", "step = 0.01", "rtol = 1e-10"});
  ExampleRun run("spherical_pendulum");
  if (!run.check_structure()) return;
  const double drift = relative_energy_drift(run.dataset("energy"));
  std::printf("spherical_pendulum: relative energy drift %.3e\n", drift);
  EXPECT_LT(drift, 5e-10);

  const Matrix h = run.dataset("angular_momentum");
  const std::size_t z = run.column("angular_momentum", "z");
  const double h0 = h(0, z);
  double h_drift = 0.0;
  for (std::size_t r = 0; r < h.rows(); ++r) h_drift = std::max(h_drift, std::abs(h(r, z) - h0));
  // H_z(0) = I_zz w_z about the pivot with the rod tilted 30 degrees: clearly non-zero.
  EXPECT_GT(std::abs(h0), 0.1);
  std::printf("spherical_pendulum: H_z(0) = %.6f kg m^2/s, relative H_z drift %.3e\n", h0, h_drift / std::abs(h0));
  // Measured 1.8e-10 (relative to |H_z(0)|, which is small: the spin is slow
  // and the rod slender); bound ~10x that.
  EXPECT_LT(h_drift / std::abs(h0), 2e-9);
  // The horizontal components are not conserved (gravity's moment): the test
  // would be vacuous if angular momentum were constant in every direction.
  const std::size_t x = run.column("angular_momentum", "x");
  double hx_change = 0.0;
  for (std::size_t r = 0; r < h.rows(); ++r) hx_change = std::max(hx_change, std::abs(h(r, x) - h(0, x)));
  EXPECT_GT(hx_change, 1e-2);
}

TEST(Examples, DoublePendulumConservesEnergy) {
  expect_job_says("double_pendulum", {"end_time = 10.0", "step = 0.01", "rtol = 1e-10"});
  ExampleRun run("double_pendulum");
  if (!run.check_structure()) return;
  const double drift = relative_energy_drift(run.dataset("energy"));
  std::printf("double_pendulum: relative energy drift %.3e\n", drift);
  EXPECT_LT(drift, 2e-7);
}

TEST(Examples, Chain10ConservesEnergy) {
  expect_job_says("chain10", {"end_time = 3.0", "step = 0.005", "rtol = 1e-9", "links = 10"});
  ExampleRun run("chain10");
  if (!run.check_structure()) return;
  const double drift = relative_energy_drift(run.dataset("energy"));
  std::printf("chain10: relative energy drift %.3e\n", drift);
  EXPECT_LT(drift, 2e-8);
}

TEST(Examples, YTreeDampersOnlyDissipateEnergy) {
  expect_job_says("y_tree", {"end_time = 5.0", "step = 0.01", "rtol = 1e-9", "damping = 0.05"});
  ExampleRun run("y_tree");
  if (!run.check_structure()) return;
  const Matrix e = run.dataset("energy");
  const double e0 = e(0, 3);
  const double scale = std::abs(e(0, 0)) + std::abs(e(0, 1)) + std::abs(e(0, 2));
  // Integration error allowed in any energy rise: 1e-7 of the energy scale,
  // ~100x rtol (see the bounds above).
  const double tolerance = 1e-7 * scale;
  double worst_rise = -1e300, worst_above_start = -1e300;
  for (std::size_t r = 1; r < e.rows(); ++r) {
    worst_rise = std::max(worst_rise, e(r, 3) - e(r - 1, 3));
    worst_above_start = std::max(worst_above_start, e(r, 3) - e0);
  }
  std::printf(
      "y_tree: E0 = %.6f J, E(end) = %.6f J, largest rise between outputs %.3e J, "
      "largest E - E0 %.3e J (tolerance %.1e J)\n",
      e0, e(e.rows() - 1, 3), worst_rise, worst_above_start, tolerance);
  EXPECT_LE(worst_rise, tolerance);
  EXPECT_LE(worst_above_start, tolerance);
  // The dampers do act: a visible part of the energy is gone by the end.
  EXPECT_LT(e(e.rows() - 1, 3), e0 - 0.01 * scale);
  // Springs are part of the energy balance.
  double max_spring = 0.0;
  for (std::size_t r = 0; r < e.rows(); ++r) max_spring = std::max(max_spring, e(r, 2));
  EXPECT_GT(max_spring, 0.0);
}

TEST(Examples, CranePayloadCableCarriesTheWeightAndTheBaseWorks) {
  expect_job_says("crane_payload", {"end_time = 60.0", "step = 0.1", "mass = 20.0", "mass = 2000.0", "links = 4"});
  ExampleRun run("crane_payload");
  if (!run.check_structure()) return;
  const double weight = (2000.0 + 4 * 20.0) * 9.81;  // container + 4 cable segments, N

  const Matrix reaction = run.dataset("joint_reaction");
  const std::size_t z = run.column("joint_reaction", "cable1.z");
  double sum = 0.0, smallest = 1e300, largest = -1e300;
  for (std::size_t r = 0; r < reaction.rows(); ++r) {
    sum += reaction(r, z);
    smallest = std::min(smallest, reaction(r, z));
    largest = std::max(largest, reaction(r, z));
  }
  const double mean = sum / static_cast<double>(reaction.rows());
  std::printf(
      "crane_payload: cable1 vertical reaction mean %.1f N (weight %.1f N, ratio %.5f), "
      "min %.1f N, max %.1f N\n",
      mean, weight, mean / weight, smallest, largest);
  EXPECT_GT(smallest, 0.0) << "the cable pushes down at some time";
  // The tension column is the norm of the three reaction components (to
  // rounding: both are computed from the same vector).
  const Matrix magnitude = run.dataset("joint_reaction_magnitude");
  const std::size_t x = run.column("joint_reaction", "cable1.x"), y = run.column("joint_reaction", "cable1.y");
  const std::size_t m = run.column("joint_reaction_magnitude", "cable1.magnitude");
  for (std::size_t r = 0; r < reaction.rows(); ++r)
    EXPECT_NEAR(magnitude(r, m), std::hypot(reaction(r, x), reaction(r, y), reaction(r, z)), 1e-12 * weight);
  EXPECT_NEAR(mean / weight, 1.0, 0.03);
  // The base's motion (and the payload's swing) modulates the tension.
  EXPECT_GT(largest - smallest, 0.01 * weight);

  const Matrix e = run.dataset("energy");
  const double scale = std::abs(e(0, 0)) + std::abs(e(0, 1)) + std::abs(e(0, 2));
  double change = 0.0;
  for (std::size_t r = 0; r < e.rows(); ++r) change = std::max(change, std::abs(e(r, 3) - e(0, 3)));
  std::printf("crane_payload: max |E - E0| / scale %.3e\n", change / scale);
  EXPECT_GT(change / scale, 1e-3) << "the moving base should do work on the tree";

  // The base heaves about [0, 0, 30] m with the sea: `treedyn check` gives its
  // standard deviation through the RAO as 0.33 m; the nominal sea (phase_seed
  // 11) reaches 0.77 m in these 60 s. Bounds: the mean of 60 s within 0.2 m of
  // 30 (the 0.3 m motion has periods of 2-16 s), no excursion beyond 1.5 m
  // (4.5 standard deviations), and it moves (std above 0.15 m).
  const Matrix base = run.dataset("base");
  const std::size_t bz = run.column("base", "position.z");
  double base_sum = 0.0, base_sum2 = 0.0;
  for (std::size_t r = 0; r < base.rows(); ++r) {
    EXPECT_NEAR(base(r, bz), 30.0, 1.5);
    base_sum += base(r, bz);
    base_sum2 += base(r, bz) * base(r, bz);
  }
  const double base_mean = base_sum / static_cast<double>(base.rows());
  EXPECT_NEAR(base_mean, 30.0, 0.2);
  EXPECT_GT(std::sqrt(base_sum2 / static_cast<double>(base.rows()) - base_mean * base_mean), 0.15);
}

TEST(Examples, KapitzaRodStaysUpright) {
  expect_job_says("kapitza", {"end_time = 5.0", "step = 0.002", "frequency = 50.0"});
  ExampleRun run("kapitza");
  if (!run.check_structure()) return;
  const Matrix angle = run.dataset("joint_angle");
  const std::size_t c = run.column("joint_angle", "rod.angle");
  double lowest = 1e300;
  for (std::size_t r = 0; r < angle.rows(); ++r) {
    lowest = std::min(lowest, angle(r, c));
    EXPECT_GT(angle(r, c), std::numbers::pi / 2) << "fell over at t = " << run.time().data[r];
  }
  EXPECT_NEAR(angle(0, c), 165.0 * std::numbers::pi / 180.0, 1e-9);  // started 15 deg off upright
  std::printf("kapitza: lowest joint angle %.4f rad (%.2f deg from hanging)\n", lowest,
              lowest * 180.0 / std::numbers::pi);
}

// ---------------------------------------------------------------------------
// check, --version, --help

TEST(ExamplesCheck, CheckPrintsTheTreeAndOkForEveryExample) {
  for (const std::string name :
       {"spherical_pendulum", "double_pendulum", "chain10", "y_tree", "crane_payload", "kapitza"}) {
    SCOPED_TRACE(name);
    const Example& e = example(name);
    TempDir dir("examples_test_check");
    const auto r = run_treedyn({"check", job_path(e).string()}, dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const std::string count = std::to_string(e.bodies.size()) + (e.bodies.size() == 1 ? " body" : " bodies");
    EXPECT_NE(r.out.find("tree (" + count + "):\nbase\n"), std::string::npos) << r.out;
    for (const auto& b : e.bodies)
      EXPECT_NE(r.out.find("-- " + b + "  ("), std::string::npos) << "body " << b << "\n" << r.out;
    const std::string ok = job_path(e).string() + ": OK\n";
    ASSERT_GE(r.out.size(), ok.size());
    EXPECT_EQ(r.out.substr(r.out.size() - ok.size()), ok) << r.out;
    // check writes nothing.
    EXPECT_TRUE(fs::is_empty(dir.path()));
  }
}

TEST(ExamplesCheck, CheckDrawsTheBranchesOfTheYTree) {
  TempDir dir("examples_test_check");
  const auto r = run_treedyn({"check", job_path(example("y_tree")).string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("base\n"
                       "`-- trunk  (3 kg, subtree 6 kg)\n"
                       "    |-- left_arm  (1 kg, subtree 1.5 kg)\n"
                       "    |   `-- left_hand  (0.5 kg, subtree 0.5 kg)\n"
                       "    `-- right_arm  (1 kg, subtree 1.5 kg)\n"
                       "        `-- right_hand  (0.5 kg, subtree 0.5 kg)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("total mass 6 kg"), std::string::npos) << r.out;
}

TEST(ExamplesCli, VersionPrintsTheVersion) {
  TempDir dir("examples_test_cli");
  const auto r = run_treedyn({"--version"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, std::string("treedyn ") + TREEDYN_VERSION + "\n");
}

// Every exit code the commands use, in the top-level help.
TEST(ExamplesCli, HelpListsEveryExitCode) {
  TempDir dir("examples_test_cli");
  const auto r = run_treedyn({"--help"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* code : {"0 ok", "1 internal error", "2 bad input", "3 integration failure", "4 output (I/O) failure",
                           "5 interrupted", "6 not enough memory"})
    EXPECT_NE(r.out.find(code), std::string::npos) << code << " in\n" << r.out;
}

TEST(ExamplesCli, RunHelpExitsZeroAndDescribesTheOptions) {
  TempDir dir("examples_test_cli");
  const auto r = run_treedyn({"run", "--help"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("JOB"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--output"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--quiet"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
