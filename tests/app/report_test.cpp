// `treedyn report` on the output of every shipped example (its ensemble,
// with fewer samples, and one trajectory), provenance and strings in every
// file, and the refusals: a file that is not HDF5 or not treedyn's, an
// older layout, an unknown --quantity, a missing matplotlib.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

const std::vector<std::string> kExamples = {"spherical_pendulum", "double_pendulum", "chain10", "y_tree",
                                            "crane_payload",      "kapitza"};
const std::string kPython = "/usr/bin/python3";
const std::string kChecks = std::string(TREEDYN_TEST_SUPPORT_DIR) + "/report_checks.py";

// The example's job with a small ensemble: 8 samples (saltelli: base 4).
std::string small_ensemble(const std::string& name) {
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/" + name + ".toml");
  const std::size_t at = text.find("[ensemble]");
  if (at == std::string::npos) throw std::runtime_error(name + " has no [ensemble]");
  const bool saltelli = text.find("design = \"saltelli\"", at) != std::string::npos;
  std::string tail = text.substr(at);
  tail = std::regex_replace(tail, std::regex("\nsamples = [0-9]+"), saltelli ? "\nsamples = 4" : "\nsamples = 8",
                            std::regex_constants::format_first_only);
  return text.substr(0, at) + tail;
}

// The lines of `text` before the first that starts with "wrote ".
std::string before_wrote(const std::string& text) {
  const std::size_t at = text.find("\nwrote ");
  return at == std::string::npos ? text : text.substr(0, at + 1);
}

CommandResult treedyn(const std::vector<std::string>& args, const fs::path& capture) {
  return run_command(TREEDYN_BINARY, args, capture);
}

void expect_figures(const fs::path& dir) {
  const CommandResult check = run_command(kPython, {kChecks, "pngs", dir.string()}, dir.parent_path() / "capture");
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_EQ(check.out.rfind("ok ", 0), 0u) << check.out;
}

class Report : public ::testing::TestWithParam<std::string> {};

// The ensemble's report: every figure there and not blank; its text summary
// is the ensemble's own end-of-run summary, and its numbers are the file's.
TEST_P(Report, EnsembleOfTheExample) {
  if (const std::string why = skipped_when_sanitized(GetParam(), true); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path job = dir.path() / "job.toml", out = dir.path() / "e.h5", report = dir.path() / "page";
  write_text(job, small_ensemble(GetParam()));
  const CommandResult e =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string()}, dir.path() / "capture");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const CommandResult r = treedyn({"report", out.string(), "-o", report.string()}, dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(before_wrote(r.out), before_wrote(e.out)) << "one summary, two commands";
  EXPECT_NE(r.out.find("wrote " + (report / "index.html").string()), std::string::npos) << r.out;
  EXPECT_EQ(read_text(report / "summary.txt"), before_wrote(e.out));
  expect_figures(report);

  // "  quantity column mean +- std [low, high]" against /stats at the last time.
  H5File f(out);
  ASSERT_TRUE(f.ok());
  const std::regex line(R"(^  (\S+)\s+(\S+)\s+(\S+) \+- (\S+)  \[\s*(\S+),\s*(\S+)\]$)");
  std::istringstream lines(r.out);
  std::size_t checked = 0;
  for (std::string l; std::getline(lines, l);) {
    std::smatch m;
    if (!std::regex_match(l, m, line)) continue;
    const std::string q = m[1], column = m[2];
    const auto columns = read_string_attribute(f.id(), "/stats/" + q + "/mean", "columns");
    const auto c = static_cast<std::size_t>(std::find(columns.begin(), columns.end(), column) - columns.begin());
    ASSERT_LT(c, columns.size()) << l;
    const auto mean = read_doubles(f.id(), "/stats/" + q + "/mean"), sd = read_doubles(f.id(), "/stats/" + q + "/std");
    const std::size_t last = mean.size() / columns.size() - 1;
    const double m_file = mean[last * columns.size() + c], s_file = sd[last * columns.size() + c];
    // Printed with %.6g and %.3g.
    EXPECT_NEAR(std::stod(m[3]), m_file, 5e-6 * std::abs(m_file) + 1e-300) << l;
    EXPECT_NEAR(std::stod(m[4]), s_file, 5e-3 * std::abs(s_file) + 1e-300) << l;
    ++checked;
  }
  EXPECT_GT(checked, 0u) << r.out;
  // The page's answers table: every response's mean ± standard error as in /responses (%.6g, %.3g).
  const std::string page = read_text(report / "index.html");
  if (exists(f.id(), "/responses")) {
    const auto names = read_string_attribute(f.id(), "/samples/responses", "columns");
    const auto units = read_string_attribute(f.id(), "/samples/responses", "column_units");
    for (std::size_t k = 0; k < names.size(); ++k) {
      char cell[160];
      std::snprintf(cell, sizeof cell, "<td>%s</td><td>%.6g ± %.3g %s", names[k].c_str(),
                    read_doubles(f.id(), "/responses/" + names[k] + "/mean").at(0),
                    read_doubles(f.id(), "/responses/" + names[k] + "/sem").at(0), units[k].c_str());
      EXPECT_NE(page.find(cell), std::string::npos) << cell;
    }
    EXPECT_LT(page.find("<h2>Answers</h2>"), page.find("<img")) << "the answers come before any figure";
  }
  // Per-sample reductions of mixed-unit quantities say each column's unit.
  if (exists(f.id(), "/samples/final/base")) {
    EXPECT_EQ(read_string_attribute(f.id(), "/samples/final/base", "column_units").size(), 9u);
  }
  // Strings read as str, and the provenance is there.
  const CommandResult s = run_command(kPython, {kChecks, "strings", out.string()}, dir.path() / "capture");
  EXPECT_EQ(s.exit_code, 0) << s.out << s.err;
}

TEST_P(Report, TrajectoryOfTheExample) {
  if (const std::string why = skipped_when_sanitized(GetParam(), true); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "t.h5";
  const CommandResult run =
      treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/" + GetParam() + ".toml", "-o", out.string(), "-q"},
              dir.path() / "capture");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CommandResult r = treedyn({"report", out.string()}, dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("trajectory: "), std::string::npos) << r.out;
  expect_figures(dir.path() / "t_report");  // the default directory: FILE without .h5, plus _report
  const CommandResult s = run_command(kPython, {kChecks, "strings", out.string()}, dir.path() / "capture");
  EXPECT_EQ(s.exit_code, 0) << s.out << s.err;
  // /motion: each joint point is its CoM plus A c, segment lengths hold to 1e-8 m (a rigid tree), the
  // root's joint is on the base point; the page's 3-D view carries these poses (to its 6 decimals).
  const CommandResult m = run_command(kPython, {kChecks, "motion", out.string(), (dir.path() / "t_report").string()},
                                      dir.path() / "capture");
  EXPECT_EQ(m.exit_code, 0) << m.out << m.err;
  EXPECT_EQ(m.out.rfind("ok motion", 0), 0u) << m.out;
  // FILE.xmf beside the file (its points in FILE.motion.h5), read back with meshio's TimeSeriesReader: times,
  // poly-lines and every step's points are the file's.
  EXPECT_NE(r.out.find("wrote " + (dir.path() / "t.xmf").string()), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir.path() / "t.motion.h5"));
  const CommandResult x =
      run_command(kPython, {kChecks, "xdmf", (dir.path() / "t.xmf").string(), out.string()}, dir.path() / "capture");
  EXPECT_EQ(x.exit_code, 0) << x.out << x.err;
  EXPECT_EQ(x.out.rfind("ok xdmf", 0), 0u) << x.out;
}

// An XDMF file that cannot be written (its name taken by a directory) is a
// warning: the page is still drawn, and nothing half-written is left (no
// companion FILE.motion.h5 either).
TEST(Report, AnXdmfFileThatCannotBeWrittenIsAWarning) {
  if (const std::string why = skipped_when_sanitized("xdmf", true); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("report_xdmf");
  const fs::path out = dir.path() / "t.h5";
  ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "-o", out.string(), "-q"},
                    dir.path() / "c")
                .exit_code,
            0);
  fs::create_directory(dir.path() / "t.xmf");
  const CommandResult r = treedyn({"report", out.string()}, dir.path() / "c");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: no XDMF file: cannot write " + (dir.path() / "t.xmf").string()), std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::is_directory(dir.path() / "t.xmf"));
  EXPECT_FALSE(fs::exists(dir.path() / "t.motion.h5"));
  EXPECT_TRUE(fs::exists(dir.path() / "t_report" / "index.html"));
  for (const auto& e : fs::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// The 3-D view in headless Chromium, offline (no name resolves): no console
// error, the canvas drawn at the first and the middle frame, and different;
// every shape at every frame inside the picture (the crane's container hangs
// far below the joints); a second of playing at 4x and 1x reaches 4 and 1 s
// later.
TEST(Report, ThreeDViewDrawsTheMotionInHeadlessChromium) {
  if (!fs::exists("/usr/bin/chromium")) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  if (const std::string why = skipped_when_sanitized("3-D view", true); !why.empty()) GTEST_SKIP() << why;
  for (const std::string example : {"double_pendulum", "crane_payload"}) {
    SCOPED_TRACE(example);
    TempDir dir("report_view");
    const fs::path out = dir.path() / "t.h5";
    ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/" + example + ".toml", "-o", out.string(), "-q"},
                      dir.path() / "c")
                  .exit_code,
              0);
    ASSERT_EQ(treedyn({"report", out.string()}, dir.path() / "c").exit_code, 0);
    const CommandResult v =
        run_command(kPython, {kChecks, "view", (dir.path() / "t_report").string()}, dir.path() / "c");
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    EXPECT_EQ(v.out.rfind("ok view", 0), 0u) << v.out;
  }
}

// FILE.xmf in ParaView's three XDMF readers (the legacy XDMFReader, Xdmf3ReaderT, Xdmf3ReaderS), where
// ParaView is installed (not a dependency: apt-get install paraview python3-paraview): every time step's
// points and poly-lines are /motion's, and no reader prints anything on stderr.
TEST(Report, XdmfFileOpensInParaViewsThreeReaders) {
  if (!fs::exists("/usr/bin/pvbatch")) GTEST_SKIP() << "ParaView is not installed (apt-get install paraview)";
  if (const std::string why = skipped_when_sanitized("ParaView", true); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("report_paraview");
  const fs::path out = dir.path() / "t.h5";
  ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/crane_payload.toml", "-o", out.string(), "-q"},
                    dir.path() / "c")
                .exit_code,
            0);
  ASSERT_EQ(treedyn({"report", out.string()}, dir.path() / "c").exit_code, 0);
  const CommandResult p =
      run_command(kPython, {kChecks, "paraview", (dir.path() / "t.xmf").string(), out.string()}, dir.path() / "c");
  EXPECT_EQ(p.exit_code, 0) << p.out << p.err;
  EXPECT_EQ(p.out.rfind("ok paraview", 0), 0u) << p.out;
}

INSTANTIATE_TEST_SUITE_P(Examples, Report, ::testing::ValuesIn(kExamples),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// `treedyn report FILE | head -1`: the reader stops after one line. The
// report is written all the same, with no traceback and exit 0 (the writes
// to the closed pipe fail quietly, in treedyn and in the plotting script).
// A job whose samples fail in two ways (tests/mpi/ensemble_mpi_test.cpp's
// kFailingJob, with a response and its limit): a light tip (normal(1, 1)
// mass, so P(mass <= 0) = Phi(-1) = 0.159) is an invalid model, a fast spin
// against max_steps = 200 gives up. The page must say so first.
const std::string kFailingJob = R"(title = "report test: failing samples"
[environment]
gravity = [0.0, 0.0, -9.81]
[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 0.5
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.25]
orientation = { type = "axis_angle", axis = [1, 0, 0], angle = 30, unit = "deg" }
[[body]]
name = "tip"
shape = "sphere"
radius = 0.05
mass = 0.3
parent = "rod"
joint_on_parent = [0.0, 0.0, -0.25]
joint_on_child = [0.0, 0.0, 0.05]
[integrator]
method = "erk_dormand_prince"
max_steps = 200
[output]
end_time = 1.0
step = 0.1
quantities = ["energy", "joint_angle"]
[ensemble]
samples = 24
seed = 9
design = "monte_carlo"
[[ensemble.perturbation]]
target = "body.tip.mass"
distribution = "normal"
mean = 1.0
std = 1.0
[[ensemble.perturbation]]
target = "body.rod.angular_velocity.y"
distribution = "uniform"
lower = 0.0
upper = 50.0
[[ensemble.response]]
name = "swing"
quantity = "joint_angle"
column = "rod.angle"
reduce = "max"
limit = 1.0
fail_if = "above"
)";

TEST(Report, FailedSamplesComeFirstAndTheirOwnPageSaysWhy) {
  if (const std::string why = skipped_when_sanitized("failing samples", true); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("report_failing");
  const fs::path job = dir.path() / "failing.toml", out = dir.path() / "failing.h5";
  write_text(job, kFailingJob);
  ASSERT_EQ(run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string(), "-q"}, dir.path() / "c").exit_code,
            0);
  std::vector<long long> status;
  {
    const H5File f(out);
    status = read_integers(f.id(), "/samples/status");
  }
  const auto failed = std::find_if(status.begin(), status.end(), [](long long s) { return s == 1; });
  ASSERT_NE(failed, status.end()) << "the job must give an integration failure";
  ASSERT_GT(std::count(status.begin(), status.end(), 2), 0) << "and an invalid model";
  const long long count = std::count_if(status.begin(), status.end(), [](long long s) { return s != 0; });
  const CommandResult r = treedyn({"report", out.string()}, dir.path() / "c");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = read_text(dir.path() / "failing_report" / "index.html");
  const std::size_t alarm = page.find("<div class=\"alarm\">" + std::to_string(count) + " of 24 samples failed");
  EXPECT_NE(alarm, std::string::npos) << "a red banner with the count";
  EXPECT_LT(alarm, page.find("<img")) << "before any figure";
  EXPECT_NE(page.find("body.tip.mass: its distribution normal(mean=1, std=1) puts P = 0.16 at or below zero"),
            std::string::npos);
  const long long k = failed - status.begin();
  EXPECT_NE(page.find("--sample " + std::to_string(k) + " -o sample_" + std::to_string(k) + ".h5"), std::string::npos)
      << "the failed sample's rerun command";
  expect_figures(dir.path() / "failing_report");
  // The failed sample alone: its page opens with the failure, why and its inputs.
  const fs::path sample = dir.path() / "sample.h5";
  ASSERT_EQ(run_command(TREEDYN_ENSEMBLE_BINARY,
                        {job.string(), "--sample", std::to_string(k), "-o", sample.string(), "-q"}, dir.path() / "c")
                .exit_code,
            0);
  ASSERT_EQ(treedyn({"report", sample.string()}, dir.path() / "c").exit_code, 0);
  const std::string own = read_text(dir.path() / "sample_report" / "index.html");
  EXPECT_NE(own.find("Sample " + std::to_string(k) + " FAILED: too_much_work"), std::string::npos) << own;
  // What to change (the job's max_steps and tolerances, as `treedyn run` advises) and the rerun command,
  // and the failure time marked on the time plots.
  EXPECT_NE(own.find("<div class=\"warning\">What to change: raise [integrator] max_steps (200 steps per output "
                     "interval here), loosen the tolerances (rtol = 1e-08, atol = 1e-10), or check the model. Then "
                     "rerun this sample: "),
            std::string::npos)
      << own;
  double reached = 0.0;
  {
    const H5File f(sample);
    const hid_t group = H5Gopen2(f.id(), "/sample", H5P_DEFAULT);
    ASSERT_GE(group, 0);
    reached = read_double_attribute(group, "time_reached").at(0);
    H5Gclose(group);
  }
  char marker[96];
  std::snprintf(marker, sizeof marker, "; the red dashed line: failed at t = %.4g s</figcaption>", reached);
  EXPECT_NE(own.find(marker), std::string::npos) << marker;
  EXPECT_NE(own.find("<td>body.tip.mass</td>"), std::string::npos);
  expect_figures(dir.path() / "sample_report");
}

TEST(Report, IntoAPipeClosedAfterOneLine) {
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "t.h5";
  ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/double_pendulum.toml", "-o", out.string(), "-q"},
                    dir.path() / "capture")
                .exit_code,
            0);
  const std::string line =
      quote(TREEDYN_BINARY) + " report " + quote(out.string()) + " | head -1; exit ${PIPESTATUS[0]}";
  const CommandResult r = run_command("bash", {"-c", line}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_EQ(r.out.rfind("trajectory: ", 0), 0u) << r.out;
  EXPECT_EQ(r.err, "") << "no traceback, no error";
  EXPECT_TRUE(fs::exists(dir.path() / "t_report" / "index.html"));
}

// Every provenance attribute, non-empty, in both kinds of file.
TEST(Provenance, EveryAttributeIsThereAndNotEmpty) {
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path job = dir.path() / "job.toml", trajectory = dir.path() / "t.h5", ensemble = dir.path() / "e.h5";
  write_text(job, small_ensemble("spherical_pendulum"));
  ASSERT_EQ(treedyn({"run", job.string(), "-o", trajectory.string(), "-q"}, dir.path() / "capture").exit_code, 0);
  ASSERT_EQ(run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", ensemble.string(), "-q"}, dir.path() / "capture")
                .exit_code,
            0);
  for (const fs::path& file : {trajectory, ensemble}) {
    SCOPED_TRACE(file.string());
    H5File f(file);
    ASSERT_TRUE(f.ok());
    for (const char* name : {"start_utc", "end_utc", "host", "command_line", "job_path", "treedyn_version",
                             "git_commit", "build_type", "compiler", "sundials_version", "hdf5_version",
                             "libdeflate_version", "eigen_version", "tomlplusplus_version", "mpi_library"}) {
      ASSERT_TRUE(has_attribute(f.id(), name)) << name;
      EXPECT_NE(read_single_string_attribute(f.id(), name), "") << name;
    }
    EXPECT_EQ(read_single_string_attribute(f.id(), "job_path"), fs::absolute(job).lexically_normal().string());
    EXPECT_NE(read_single_string_attribute(f.id(), "command_line").find(job.string()), std::string::npos);
    EXPECT_GE(read_integer_attribute(f.id(), "ranks"), 1);
  }
  H5File f(ensemble);
  EXPECT_EQ(read_string_attribute(f.id(), "rank_hosts").size(), 1u);
  EXPECT_NE(read_single_string_attribute(f.id(), "mpi_library"), "none (serial)");
}

// Refusals: one line on stderr, exit 2, never a traceback.
void expect_refused(const std::vector<std::string>& args, const std::string& words, const fs::path& capture,
                    const std::vector<std::string>& prefix = {}) {
  const CommandResult r = run_command(TREEDYN_BINARY, args, capture, prefix);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(ReportRefuses, FilesItCannotReport) {
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path text = dir.path() / "notes.h5";
  write_text(text, "not hdf5\n");
  expect_refused({"report", text.string()}, "not an HDF5 file", dir.path() / "capture");
  expect_refused({"report", (dir.path() / "missing.h5").string()}, "no such file", dir.path() / "capture");
  // HDF5, but not treedyn's.
  const fs::path other = dir.path() / "other.h5";
  {
    const hid_t f = H5Fcreate(other.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t g = H5Gcreate2(f, "data", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Gclose(g);
    H5Fclose(f);
  }
  expect_refused({"report", other.string()}, "not a treedyn trajectory or ensemble file", dir.path() / "capture");
  // An older layout: a trajectory file without provenance.
  const fs::path old = dir.path() / "old.h5";
  {
    const hid_t f = H5Fcreate(old.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t one = 1;
    const hid_t space = H5Screate_simple(1, &one, nullptr);
    const hid_t set = H5Dcreate2(f, "time", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dclose(set);
    H5Sclose(space);
    H5Fclose(f);
  }
  expect_refused({"report", old.string()}, "written by an older treedyn", dir.path() / "capture");
}

// A report directory that cannot be made (a file stands there): exit 4.
TEST(ReportRefuses, ADirectoryThatCannotBeMadeIsAnIoError) {
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "t.h5", blocker = dir.path() / "page";
  ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml", "-o", out.string(), "-q"},
                    dir.path() / "capture")
                .exit_code,
            0);
  write_text(blocker, "a file, not a directory\n");
  const CommandResult r = treedyn({"report", out.string(), "-o", blocker.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.err.find("cannot create the report directory"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(blocker), "a file, not a directory\n");
}

TEST(ReportRefuses, UnknownQuantityAndMissingMatplotlib) {
  TempDir dir("report_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "t.h5";
  ASSERT_EQ(treedyn({"run", std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml", "-o", out.string(), "-q"},
                    dir.path() / "capture")
                .exit_code,
            0);
  expect_refused({"report", out.string(), "--quantity", "joint_angel"},
                 "--quantity joint_angel: not recorded in " + out.string() + "; recorded: orientation",
                 dir.path() / "capture");
  EXPECT_FALSE(fs::exists(dir.path() / "t_report")) << "nothing written for a refused report";
  // A matplotlib that does not import: the message names the package.
  const fs::path fake = dir.path() / "fake" / "matplotlib";
  fs::create_directories(fake);
  write_text(fake / "__init__.py", "raise ImportError('no matplotlib in this test')\n");
  expect_refused({"report", out.string()}, "apt-get install python3-matplotlib", dir.path() / "capture",
                 {"env", "PYTHONPATH=" + (dir.path() / "fake").string()});
}

}  // namespace
