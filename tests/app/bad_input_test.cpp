// Bad input to `treedyn run`: each case writes a small job file into a fresh
// temporary directory, runs the real command with -o into that directory and
// checks
//   - the exit code (2 = bad input, 4 = output / I/O failure),
//   - that stderr holds exactly ONE error line, "error: " followed by the job
//     file's path with the LINE:COLUMN of the offending value (where the file
//     has one), the field's name and what is allowed,
//   - that stdout is empty and no output is left behind (no x.h5, no
//     x.h5.tmp-* in the directory).
// Each case prints its exact message to stdout so it can be quoted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "support/command.hpp"

namespace {

namespace fs = std::filesystem;

using namespace treedyn::testing;

// ---------------------------------------------------------------------------
// Helpers

// Runs `treedyn ARGS`; stdout and stderr are captured in files under `capture`
// (a directory of its own, so the job's directory holds only what treedyn writes).
CommandResult run_treedyn(const std::vector<std::string>& args, const fs::path& capture) {
  return run_command(TREEDYN_BINARY, args, capture);
}

// One bad-input case: the job file, the run, and what is left in the directory.
class Case {
 public:
  // `output_for` gives the -o argument from the case's directory (default: DIR/x.h5).
  Case(const std::string& label, const std::string& job_text,
       const std::function<std::string(const fs::path&)>& output_for = {})
      : label_(label), text_(job_text) {
    fs::create_directory(dir_.path() / "capture");
    job_ = dir_.path() / "job.toml";
    write_text(job_, job_text);
    output_ = output_for ? fs::path(output_for(dir_.path())) : dir_.path() / "x.h5";
    result_ = run_treedyn({"run", job_.string(), "-o", output_.string()}, dir_.path() / "capture");
    std::printf("[%s] exit %d: %s", label.c_str(), result_.exit_code, result_.err.c_str());
    if (result_.err.empty() || result_.err.back() != '\n') std::printf("\n");
  }

  const fs::path& dir() const { return dir_.path(); }
  const std::string& text() const { return text_; }
  std::string job() const { return job_.string(); }
  std::string output() const { return output_.string(); }
  const CommandResult& result() const { return result_; }
  const std::string& err() const { return result_.err; }

  // Exit code, one "error: PREFIX..." line on stderr containing every one of
  // `parts`, nothing on stdout, no output file or temporary in the directory.
  void expect_refused(int exit_code, const std::string& prefix, std::initializer_list<std::string> parts) const {
    EXPECT_EQ(result_.exit_code, exit_code) << result_.err;
    EXPECT_EQ(result_.out, "") << "nothing should be printed on stdout";
    const std::string& e = result_.err;
    EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 1) << "expected ONE error line:\n" << e;
    EXPECT_TRUE(!e.empty() && e.back() == '\n') << e;
    EXPECT_EQ(e.rfind("error: " + prefix, 0), 0u)
        << "expected the message to start with\n  error: " << prefix << "\ngot\n  " << e;
    for (const std::string& part : parts)
      EXPECT_NE(e.find(part), std::string::npos) << "missing \"" << part << "\" in\n  " << e;
    EXPECT_EQ(e.find("HDF5-DIAG"), std::string::npos) << "HDF5's own error stack leaked:\n" << e;
    expect_no_output_left();
  }

  void expect_no_output_left() const {
    for (const auto& entry : fs::directory_iterator(dir_.path())) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(name, "x.h5") << "output file left behind";
      EXPECT_NE(name.rfind("x.h5.tmp-", 0), 0u) << "temporary file left behind: " << name;
    }
  }

 private:
  std::string label_;
  std::string text_;
  TempDir dir_{"bad_input_test"};
  fs::path job_, output_;
  CommandResult result_;
};

// A valid one-body job; the cases below change one thing in it.
const std::string kGoodJob = R"(title = "bad input"

[[body]]
name = "rod"
shape = "cylinder"
radius = 0.01
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]

[output]
end_time = 1.0
step = 0.1
)";

std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::invalid_argument("not in the job: " + from);
  return text.replace(at, from.size(), to);
}

// ---------------------------------------------------------------------------
// The reference job is accepted, so every refusal below is due to its one change.

TEST(BadInput, TheUnchangedReferenceJobRuns) {
  Case c("reference job", kGoodJob);
  EXPECT_EQ(c.result().exit_code, 0) << c.err();
  EXPECT_EQ(c.err(), "");
  EXPECT_TRUE(fs::exists(c.output()));
}

// ---------------------------------------------------------------------------
// Job file errors: exit 2

TEST(BadInput, MalformedTomlGivesTheParserPosition) {
  const std::string text = with(kGoodJob, "mass = 1.0", "mass = 1.0 kg");
  Case c("malformed TOML", text);
  // line 8 "mass = 1.0 kg": the parser stops at the 'k'.
  c.expect_refused(2, c.job() + ":" + position_of(text, "kg") + ": not valid TOML: ", {"saw 'k'"});
}

TEST(BadInput, WrongTypeNamesTheFieldAndTheExpectedType) {
  const std::string text = with(kGoodJob, "mass = 1.0", "mass = \"heavy\"");
  Case c("wrong type", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "mass = \"heavy\"") + ": body[1].mass: ",
                   {"expected a number, got a string"});
}

TEST(BadInput, UnknownKeySuggestsTheNearestAllowedKey) {
  const std::string text = with(kGoodJob, "mass = 1.0", "mas = 1.0");
  Case c("unknown key", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "mas = 1.0") + ": body[1].mas: ",
                   {"unknown key 'mas'", "did you mean 'mass'?", "Allowed here:", " mass ", " parent "});
}

TEST(BadInput, MissingRequiredParentPointsAtTheBodyTable) {
  const std::string text = with(kGoodJob, "parent = \"base\"\n", "");
  Case c("missing parent", text);
  // The key is absent, so the error points at the [[body]] header (line 3).
  c.expect_refused(
      2, c.job() + ":" + position_of(text, "[[body]]") + ": body[1].parent: ", {"missing required field", "\"base\""});
}

TEST(BadInput, NegativeMassIsRefusedWithTheAllowedRange) {
  const std::string text = with(kGoodJob, "mass = 1.0", "mass = -2.5");
  Case c("negative mass", text);
  c.expect_refused(
      2, c.job() + ":" + value_position(text, "mass = -2.5") + ": body[1].mass: ", {"-2.5", "must be positive", "kg"});
}

TEST(BadInput, UnknownSpringLawListsTheLaws) {
  const std::string text = with(kGoodJob, "joint_on_child = [0.0, 0.0, 0.5]",
                                "joint_on_child = [0.0, 0.0, 0.5]\nspring = { stiffness = 2.0, law = \"linear\" }");
  Case c("unknown spring law", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "law = \"linear\"") + ": body[1].spring.law: ",
                   {"\"linear\" is not a spring law", "\"quaternion\"", "\"rotation_vector\""});
}

TEST(BadInput, UnknownAccelerationSolverListsTheSolvers) {
  const std::string text = kGoodJob + "\n[integrator]\nsolver = \"featherstone\"\n";
  Case c("unknown solver", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "solver = \"featherstone\"") + ": integrator.solver: ",
                   {"\"featherstone\" is not an acceleration solver", "\"auto\"", "\"recursive\"", "\"sparse_ldlt\""});
}

// A chain of 3200 bodies needs more (body, ancestor) blocks than the L^T D L
// solver allows; the recursive solver (the default) has no such limit.
TEST(BadInput, TooDeepForTheSparseSolverPointsAtTheSolverField) {
  std::string bodies;
  for (int i = 0; i < 3200; ++i)
    bodies += "[[body]]\nname = \"b" + std::to_string(i) +
              "\"\nmass = 1.0\nprincipal_moments = [0.1, 0.1, 0.1]\nparent = \"" +
              (i == 0 ? std::string("base") : "b" + std::to_string(i - 1)) +
              "\"\njoint_on_child = [0.0, 0.0, 0.01]\njoint_on_parent = [0.0, 0.0, -0.01]\n";
  const std::string text = bodies + "[integrator]\nsolver = \"sparse_ldlt\"\n[output]\nend_time = 1e-3\nstep = 1e-3\n";
  Case c("too deep for sparse_ldlt", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "solver = \"sparse_ldlt\"") + ": integrator.solver: ",
                   {"too deep", "sparse_ldlt", "recursive"});
  Case recursive("3200 bodies, recursive solver", with(text, "solver = \"sparse_ldlt\"", "solver = \"auto\""));
  EXPECT_EQ(recursive.result().exit_code, 0) << recursive.err();
  EXPECT_TRUE(fs::exists(recursive.output()));
}

// Refusals found by a hostile test, each now with its FILE:LINE:COLUMN: FIELD.
TEST(BadInput, ABodyNamedBaseIsRefusedAtItsName) {
  const std::string text = with(kGoodJob, "name = \"rod\"", "name = \"base\"");
  Case c("body named base", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "name = \"base\"") + ": body[1].name: ",
                   {"reserved for the moving base point"});
}

TEST(BadInput, AForceOnAnUnknownBodySuggestsTheNearestBody) {
  const std::string text = kGoodJob + "\n[[force]]\nbody = \"rdo\"\nforce = [1.0, 0.0, 0.0]\n";
  Case c("force on an unknown body", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "body = \"rdo\"") + ": force[1].body: ",
                   {"'rdo' is not a body of the model", "did you mean 'rod'?"});
}

TEST(BadInput, AMomentOnAnUnknownBodyIsRefusedAtItsBody) {
  const std::string text = kGoodJob + "\n[[moment]]\nbody = \"wheel\"\nmoment = [1.0, 0.0, 0.0]\n";
  Case c("moment on an unknown body", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "body = \"wheel\"") + ": moment[1].body: ",
                   {"'wheel' is not a body of the model"});
}

// Each mass is finite, their sum is not: the equations would be infinite
// from t = 0 (before, `check` said OK and the run failed at t = 0).
TEST(BadInput, MassesThatOverflowTheMassMatrixAreRefusedBeforeAnyWork) {
  const std::string text =
      with(kGoodJob, "mass = 1.0", "mass = 1e308") +
      "\n[[body]]\nname = \"tip\"\nmass = 1e308\nprincipal_moments = [0.1, 0.1, 0.1]\nparent = \"rod\"\n"
      "joint_on_child = [0.0, 0.0, 0.1]\njoint_on_parent = [0.0, 0.0, -0.5]\n";
  Case c("overflowing masses", text);
  c.expect_refused(2, c.job() + ":", {"body 'rod'", "overflow double precision"});
}

// The equations evaluated once at t = 0: an initial state whose terms
// overflow (w x J w with |w| = 1e200) is refused before any work.
TEST(BadInput, AnInitialStateWhoseEquationsOverflowIsRefusedBeforeAnyWork) {
  const std::string text = with(
      kGoodJob, "joint_on_child = [0.0, 0.0, 0.5]",
      "joint_on_child = [0.0, 0.0, 0.5]\nangular_velocity = { value = [1e200, 1e200, 0.0], frame = \"inertial\" }");
  Case c("overflowing initial state", text);
  c.expect_refused(2, c.job() + ":" + position_of(text, "[[body]]") + ": ", {"body 'rod'", "not finite at t = 0 s"});
}

TEST(BadInput, ARelativeToleranceBelowDoublePrecisionIsRefused) {
  const std::string text = kGoodJob + "\n[integrator]\nrtol = 1e-300\natol = 1e-300\n";
  Case c("rtol below double precision", text);
  c.expect_refused(
      2, c.job() + ":" + value_position(text, "rtol = 1e-300") + ": integrator.rtol: ", {"1e-300", "at least 1e-15"});
}

// Debian's toml++ 3.3.0 reaches __builtin_unreachable on some non-ASCII
// input outside strings (upstream #295): such bytes never reach it.
TEST(BadInput, NonAsciiOutsideStringsAndInvalidUtf8AreRefusedBeforeTheParser) {
  {
    const std::string text = kGoodJob + "\xc6\xbb\x27\n";
    Case c("bytes c6 bb 27", text);
    c.expect_refused(2, c.job() + ":" + position_of(text, "\xc6\xbb") + ": not valid TOML: ",
                     {"non-ASCII character outside a string or comment"});
  }
  {
    const std::string text = with(kGoodJob, "title = \"bad input\"", "title = \"bad \xff input\"");
    Case c("invalid UTF-8", text);
    c.expect_refused(
        2, c.job() + ":" + position_of(text, "\xff") + ": not valid TOML: ", {"the byte 0xff is not valid UTF-8"});
  }
  // Non-ASCII inside strings and comments stays allowed.
  Case ok("non-ASCII in a string and a comment",
          with(kGoodJob, "title = \"bad input\"", "title = \"caf\xc3\xa9 \xc6\xbb'\" # \xc3\xa9t\xc3\xa9"));
  EXPECT_EQ(ok.result().exit_code, 0) << ok.err();
}

TEST(BadInput, UpperEndNeedsACylinder) {
  const std::string text =
      "[[body]]\nname = \"ball\"\nshape = \"sphere\"\nradius = 0.1\nmass = 1.0\nparent = \"base\"\n"
      "joint_on_child = \"upper_end\"\n\n[output]\nend_time = 1.0\nstep = 0.1\n";
  Case c("upper_end on a sphere", text);
  c.expect_refused(
      2, c.job() + ":" + position_of(text, "[[body]]") + ": body 'ball': ", {"\"upper_end\"", "must be a cylinder"});
}

TEST(BadInput, DimensionOfAnotherShapeIsRefused) {
  const std::string text = with(kGoodJob, "length = 1.0", "length = 1.0\nsize = [1.0, 1.0, 1.0]");
  Case c("box size on a cylinder", text);
  c.expect_refused(
      2, c.job() + ":" + value_position(text, "size = [") + ": body[1].size: ", {"not a dimension of a cylinder"});
}

// Bodies given with mass and principal moments, so each [[body]] is five lines.
std::string body(const std::string& name, const std::string& parent) {
  return "[[body]]\nname = \"" + name + "\"\nmass = 1.0\nprincipal_moments = [0.1, 0.1, 0.01]\n" + "parent = \"" +
         parent + "\"\n\n";
}
const std::string kOutput = "[output]\nend_time = 1.0\nstep = 0.1\n";

// Base-motion errors are found where the base motion is validated (one
// place, BaseMotion) and reported at the [base] table.
TEST(BadInput, TabulatedBaseTimesOutOfOrderPointAtTheBaseTable) {
  const std::string text =
      "title = \"base\"\n\n[base]\ntype = \"tabulated\"\n"
      "times = [0.0, 1.0, 0.5]\npositions = [[0, 0, 0], [0, 0, 1], [0, 0, 2]]\n\n" +
      body("root", "base") + kOutput;
  Case c("tabulated base, times out of order", text);
  c.expect_refused(2, c.job() + ":" + position_of(text, "[base]") + ": ",
                   {"base motion 'tabulated'", "strictly increasing", "sample 3"});
}

// A sea state's fields are checked where they are read, each at its value.
std::string sea_job(const std::string& axis_z) {
  return "title = \"sea\"\n\n[base]\ntype = \"sea_state\"\n\n[base.z]\n" + axis_z + "\n" + body("root", "base") +
         kOutput;
}

TEST(BadInput, SeaStateFieldsAreRefusedAtTheirValues) {
  struct Bad {
    std::string axis, at, field;
    std::vector<std::string> says;
  };
  // clang-format off
  const std::vector<Bad> cases = {
      {"spectrum = \"bretschneider\"\nsignificant_height = 2.0\npeak_period = 8.0\n", "spectrum = \"bretschneider\"",
       "base.z.spectrum", {"not a wave spectrum", "\"jonswap\", \"pierson_moskowitz\", \"tabulated\""}},
      {"significant_height = -2.0\npeak_period = 8.0\n", "significant_height = -2.0", "base.z.significant_height",
       {"must be a finite number > 0 m"}},
      {"significant_height = 2.0\n", "", "base.z.peak_period", {"missing required field"}},
      {"spectrum = \"pierson_moskowitz\"\nsignificant_height = 2.0\npeak_period = 8.0\ngamma = 3.3\n",
       "gamma = 3.3", "base.z.gamma", {"Pierson-Moskowitz has no peak enhancement"}},
      {"significant_height = 2.0\npeak_period = 8.0\ncomponents = 0\n", "components = 0", "base.z.components",
       {"from 1 to 10000"}},
      {"spectrum = \"tabulated\"\nfrequencies = [0.1, 0.2]\ndensities = [1.0, 1.0]\npeak_period = 8.0\n",
       "peak_period = 8.0", "base.z.peak_period", {"a tabulated spectrum is given by frequencies and densities"}},
      {"significant_height = 2.0\npeak_period = 8.0\n[base.z.rao]\nfrequencies = [0.1, 0.2]\ngains = [1.0, 1.0]\n",
       "[base.z.rao]", "base.z.rao", {"rao: its frequencies [0.1, 0.2] Hz must cover the band of the components [0.0625, 0.4375] Hz"}},
      {"significant_height = 2.0\npeak_period = 8.0\nwave_height = 1.0\n", "wave_height = 1.0", "base.z.wave_height",
       {"unknown key"}},
      {"significant_height = 2.0\npeak_period = 8.0\nmax_frequency = 0.01\n", "max_frequency = 0.01",
       "base.z.max_frequency", {"the band [0.0625, 0.01] Hz is not allowed"}},
      {"significant_height = 2.0\npeak_period = 8.0\ngamma = 0.5\n", "gamma = 0.5", "base.z.gamma",
       {"must be from 1 (Pierson-Moskowitz) to 20"}},
      {"spectrum = \"tabulated\"\nfrequencies = [0.1, 0.2]\ndensities = [1.0, 1.0]\nmin_frequency = 0.05\n",
       "min_frequency = 0.05", "base.z.min_frequency", {"reaches outside the tabulated spectrum's frequencies [0.1, 0.2]"}},
      {"spectrum = \"tabulated\"\nfrequencies = [0.1, 0.2]\ndensities = [0.0, 0.0]\n", "densities = [0.0, 0.0]",
       "base.z.densities", {"no energy"}},
      {"spectrum = \"tabulated\"\nfrequencies = [0.1, 0.2]\ndensities = [1.0, -1.0]\n", "densities = [1.0, -1.0]",
       "base.z.densities", {"value >= 0"}},
      {"significant_height = 2.0\npeak_period = 8.0\n[base.z.rao]\nfrequencies = [0.0, 1.0]\ngains = [1.0, 1.0]\n"
       "unit = \"deg\"\n", "unit = \"deg\"", "base.z.rao.unit", {"it has no phases"}},
  };
  // clang-format on
  for (const Bad& b : cases) {
    const std::string text = sea_job(b.axis);
    Case c("sea state: " + b.field, text);
    const std::string where = b.at.empty()     ? position_of(text, "[base.z]")
                              : b.at[0] == '[' ? position_of(text, b.at)
                                               : value_position(text, b.at);
    const std::string prefix = c.job() + ":" + where + ": " + b.field + ": ";
    EXPECT_EQ(c.result().exit_code, 2) << c.err();
    EXPECT_EQ(c.err().rfind("error: " + prefix, 0), 0u) << "expected error: " << prefix << "\ngot " << c.err();
    for (const std::string& part : b.says) EXPECT_NE(c.err().find(part), std::string::npos) << c.err();
    c.expect_no_output_left();
  }
}

TEST(BadInput, AnAxisFollowingWavesNeedsAnAxisWithWavesAndAnRao) {
  const std::string own = "significant_height = 2.0\npeak_period = 8.0\n\n";
  for (const auto& [y, at, says] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"wave = \"x\"\n[base.y.rao]\nfrequencies = [0.0, 1.0]\ngains = [1.0, 1.0]\n", "wave = \"x\"",
            "not an axis with waves of its own"},
           {"wave = \"z\"\n", "wave = \"z\"", "needs its own [base.AXIS.rao]"},
           {"wave = \"z\"\nsignificant_height = 1.0\n", "significant_height = 1.0", "unknown key"}}) {
    const std::string text = sea_job(own + "[base.y]\n" + y);
    Case c("sea state follower", text);
    EXPECT_EQ(c.result().exit_code, 2) << c.err();
    EXPECT_EQ(c.err().rfind("error: " + c.job() + ":" + value_position(text, at) + ": base.y.", 0), 0u) << c.err();
    EXPECT_NE(c.err().find(says), std::string::npos) << c.err();
    c.expect_no_output_left();
  }
}

TEST(BadInput, CycleBetweenTwoBodiesIsNotATree) {
  // root hangs from the base; a and b name each other as parent.
  const std::string text = "title = \"cycle\"\n\n" + body("root", "base") + body("a", "b") + body("b", "a") + kOutput;
  Case c("cycle between two bodies", text);
  // Points at the [[body]] table of 'a', the first body of the loop (line 9).
  c.expect_refused(2, c.job() + ":" + position_of(text, "[[body]]\nname = \"a\"") + ": body 'a': ",
                   {"cycle", "parents", "must form a tree"});
}

TEST(BadInput, CycleWithNothingOnTheBaseSaysABodyMustHangFromTheBase) {
  // Only a <-> b: no body reaches the base. The message points at the first
  // body of the loop and says why it never reaches the base.
  const std::string text = body("a", "b") + body("b", "a") + kOutput;
  Case c("two-body cycle, nothing on the base", text);
  c.expect_refused(2, c.job() + ":" + position_of(text, "[[body]]\nname = \"a\"") + ": body 'a': ",
                   {"no body is attached to 'base'", "cycle", "parent 'base'"});
}

TEST(BadInput, SelfParentIsNotATree) {
  const std::string text = "title = \"self\"\n\n" + body("root", "base") + body("a", "a") + kOutput;
  Case c("self-parent", text);
  c.expect_refused(2, c.job() + ":" + position_of(text, "[[body]]\nname = \"a\"") + ": body 'a': ",
                   {"its own parent", "two different bodies"});
}

// A body error raised by the model's validation (cycle; inertia) is prefixed
// with the body's name by the reader; the message must not say it twice.
TEST(BadInput, ModelErrorsNameTheBodyOnlyOnce) {
  {
    const std::string text = "title = \"cycle\"\n\n" + body("root", "base") + body("a", "b") + body("b", "a") + kOutput;
    Case c("cycle, repeated name check", text);
    EXPECT_EQ(c.err().find("body 'a': body 'a':"), std::string::npos) << c.err();
  }
  {
    const std::string text = with(body("rod", "base"), "[0.1, 0.1, 0.01]", "[1.0, 1.0, 5.0]") + kOutput;
    Case c("inertia violates the triangle inequality", text);
    EXPECT_EQ(c.result().exit_code, 2);
    EXPECT_NE(c.err().find("triangle inequality"), std::string::npos) << c.err();
    EXPECT_EQ(c.err().find("body 'rod': body 'rod':"), std::string::npos) << c.err();
    c.expect_no_output_left();
  }
}

TEST(BadInput, AngleUnitDegreesIsRefusedWithTheAllowedUnits) {
  const std::string text =
      with(kGoodJob, "joint_on_child = [0.0, 0.0, 0.5]\n",
           "joint_on_child = [0.0, 0.0, 0.5]\n"
           "orientation = { type = \"axis_angle\", axis = [1, 0, 0], angle = 30, unit = \"degrees\" }\n");
  Case c("bad angle unit", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "unit = \"degrees\"") + ": body[1].orientation.unit: ",
                   {"\"degrees\" is not an angle unit", "allowed: \"deg\" or \"rad\""});
}

TEST(BadInput, EndTimeZeroIsRefused) {
  const std::string text = with(kGoodJob, "end_time = 1.0", "end_time = 0.0");
  Case c("end time zero", text);
  c.expect_refused(2,
                   c.job() + ":" + value_position(text, "end_time = 0.0") + ": output.end_time: ", {"must be > 0 s"});
}

TEST(BadInput, NegativeEndTimeIsRefused) {
  const std::string text = with(kGoodJob, "end_time = 1.0", "end_time = -2.0");
  Case c("negative end time", text);
  c.expect_refused(
      2, c.job() + ":" + value_position(text, "end_time = -2.0") + ": output.end_time: ", {"-2", "must be > 0 s"});
}

TEST(BadInput, OutputStepLargerThanEndTimeIsRefused) {
  const std::string text = with(kGoodJob, "step = 0.1", "step = 2.0");
  Case c("output step larger than the end time", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "step = 2.0") + ": output.step: ",
                   {"larger than the end time", "at most end_time"});
}

// An absurdly small step would ask for more output times than fit in memory
// (end/step overflowed a 64-bit count once and crashed the reader).
TEST(BadInput, TinyOutputStepIsRefusedNotACrash) {
  const std::string text = with(kGoodJob, "step = 0.1", "step = 1e-30");
  Case c("tiny output step", text);
  c.expect_refused(2, c.job() + ":" + value_position(text, "step = 1e-30") + ": output.step: ",
                   {"more than 10 million output times"});
}

// Values quoted in messages are formatted with std::to_string ("%f"), so
// small values lose all their digits: a step of 2e-7 s "is larger than the
// end time 0.000000 s", a mass of -1e-9 kg is "-0.000000". The refusal itself
// is right (exit 2, right place); the message must show the values given.
TEST(BadInput, SmallValuesAreQuotedWithTheirDigits) {
  {
    const std::string text = with(with(kGoodJob, "end_time = 1.0", "end_time = 1e-7"), "step = 0.1", "step = 2e-7");
    Case c("tiny output step larger than a tiny end time", text);
    c.expect_refused(
        2, c.job() + ":" + value_position(text, "step = 2e-7") + ": output.step: ", {"larger than the end time"});
    EXPECT_EQ(c.err().find("0.000000"), std::string::npos) << c.err();
  }
  {
    const std::string text = with(kGoodJob, "mass = 1.0", "mass = -1e-9");
    Case c("tiny negative mass", text);
    c.expect_refused(2,
                     c.job() + ":" + value_position(text, "mass = -1e-9") + ": body[1].mass: ", {"must be positive"});
    EXPECT_EQ(c.err().find("0.000000"), std::string::npos) << c.err();
  }
}

TEST(BadInput, MissingJobFileIsBadInput) {
  TempDir dir("bad_input_test");
  const fs::path job = dir.path() / "no_such_job.toml";
  const fs::path capture = dir.path() / "capture";
  fs::create_directory(capture);
  const auto r = run_treedyn({"run", job.string(), "-o", (dir.path() / "x.h5").string()}, capture);
  std::printf("[missing job file] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "error: " + job.string() + ": cannot open the job file for reading\n");
  EXPECT_FALSE(fs::exists(dir.path() / "x.h5"));
}

TEST(BadInput, ARefusedJobLeavesAnExistingOutputFileUntouched) {
  TempDir dir("bad_input_test");
  const fs::path output = dir.path() / "x.h5", job = dir.path() / "job.toml";
  const fs::path capture = dir.path() / "capture";
  fs::create_directory(capture);
  write_text(output, "previous results");
  write_text(job, with(kGoodJob, "mass = 1.0", "mass = -1.0"));
  const auto r = run_treedyn({"run", job.string(), "-o", output.string()}, capture);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(read_text(output), "previous results");
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_NE(entry.path().filename().string().rfind("x.h5.tmp-", 0), 0u);
}

// The largest supported model is 10,000 bodies, counted before anything is
// built: a 1 KB job of 100 chains of 3000 links is refused at the fourth
// chain's `links` at once (it used to build 300,000 bodies first), and a job
// of 10,001 [[body]] tables at the last one's name. 10,000 are accepted.
TEST(BadInput, ModelsOverTenThousandBodiesAreRefusedBeforeAnythingIsBuilt) {
  std::string chains = "[output]\nend_time = 0.01\nstep = 0.01\n";
  for (int k = 0; k < 100; ++k)
    chains += "\n[[chain]]\nname = \"c" + std::to_string(k) + "\"\nlinks = 3000\nlink_length = 0.1\nmass = 0.1\n" +
              (k ? "parent = \"c" + std::to_string(k - 1) + "3000\"\n" : "");
  Case c("100 chains of 3000 links", chains);
  c.expect_refused(2,
                   c.job() + ":" +
                       value_position(chains, "links = 3000\nlink_length = 0.1\nmass = 0.1\nparent = \"c23000") +
                       ": chain[4].links: ",
                   {"with this table the model has 12000 bodies; treedyn supports at most 10000",
                    "one right-hand side takes about"});
  EXPECT_LT(c.result().seconds, 10.0) << "refused before building anything";

  std::string bodies = "[output]\nend_time = 0.01\nstep = 0.01\n";
  for (int k = 0; k <= 10000; ++k)
    bodies += "\n[[body]]\nname = \"b" + std::to_string(k) + "\"\nmass = 1.0\ninertia = 0.01\nparent = \"" +
              (k ? "b" + std::to_string(k - 1) : std::string("base")) + "\"\n";
  Case d("10,001 bodies", bodies);
  d.expect_refused(2, d.job() + ":" + value_position(bodies, "name = \"b10000\"") + ": body[10001].name: ",
                   {"with this table the model has 10001 bodies"});

  const std::string at_limit = with(chains, "links = 3000\nlink_length = 0.1\nmass = 0.1\nparent = \"c23000\"",
                                    "links = 1000\nlink_length = 0.1\nmass = 0.1\nparent = \"c23000\"");
  const std::string four = at_limit.substr(0, at_limit.find("\n[[chain]]\nname = \"c4\""));
  TempDir dir("bad_input_test");
  write_text(dir.path() / "four.toml", four);
  const CommandResult r =
      run_command(TREEDYN_BINARY, {"check", (dir.path() / "four.toml").string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("10000 bodies"), std::string::npos) << r.out.substr(0, 200);
}

// ---------------------------------------------------------------------------
// Output errors: exit 4

TEST(BadOutput, OutputDirectoryThatDoesNotExistIsAnIoError) {
  Case c("output directory does not exist", kGoodJob,
         [](const fs::path& dir) { return (dir / "missing" / "x.h5").string(); });
  const std::string missing = (c.dir() / "missing").string();
  c.expect_refused(4, "output " + c.output() + ": ", {"directory " + missing + " does not exist", "create it first"});
  EXPECT_FALSE(fs::exists(c.dir() / "missing")) << "treedyn should not create the directory";
}

TEST(BadOutput, OutputPathThatIsAnExistingDirectoryIsAnIoError) {
  Case c("output path is an existing directory", kGoodJob, [](const fs::path& dir) {
    fs::create_directory(dir / "out");
    return (dir / "out").string();
  });
  c.expect_refused(4, "output " + c.output() + ": is a directory; ",
                   {"give a file name such as " + (c.dir() / "out" / "result.h5").string()});
  EXPECT_TRUE(fs::is_directory(c.dir() / "out"));
  EXPECT_TRUE(fs::is_empty(c.dir() / "out")) << "nothing may be written into the directory";
}

TEST(BadOutput, OutputFileThatCannotBeCreatedIsAnIoError) {
  // /proc accepts no new files, not even for root. As root the directory
  // passes the access() check and HDF5's create fails after integrating; as
  // another user the directory is refused up front. Either way: exit 4, one
  // message naming the output path, and no file.
  Case c("output file cannot be created", kGoodJob,
         [](const fs::path&) { return std::string("/proc/treedyn_test.h5"); });
  c.expect_refused(4, "output /proc/treedyn_test.h5: ", {});
  const std::string& e = c.err();
  EXPECT_TRUE(e.find("cannot create the file") != std::string::npos || e.find("is not writable") != std::string::npos)
      << e;
  for (const auto& entry : fs::directory_iterator("/proc"))
    EXPECT_NE(entry.path().filename().string().rfind("treedyn_test.h5", 0), 0u) << entry.path();
}

}  // namespace
