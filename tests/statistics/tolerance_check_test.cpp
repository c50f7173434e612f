// The pilot's tolerance check (statistics/tolerance_check.*) on responses
// built by hand, where every number is exact, and through the ensemble on a
// pendulum integrated far too loosely and as the examples are.
#include "statistics/tolerance_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "support/command.hpp"
#include "support/ensemble_run.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::statistics;
using namespace treedyn::testing;
namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Two responses over 6 pilot samples (sample 2 failed); responses 0 .. 5 of
// the first are 1, 2, -, 4, 5, 6 (mean 3.6, std sqrt(17.2 / 4) = 2.0736); the
// reruns of samples 0, 1, 3 (2 failed, so it says nothing) change the first
// by 0.01, 0.03, 0.02 and leave the second, a level never crossed (+inf),
// as it was.
TEST(ToleranceCheck, LargestChangeOverTheRerunsAgainstThePilotSpread) {
  const std::vector<double> pilot{1, kInf, 2, kInf, kNaN, kNaN, 4, kInf, 5, 7, 6, 9};
  const std::vector<double> rerun{1.01, kInf, 2.03, kInf, 3, 3, 4.02, kInf};
  const ToleranceCheck c = check_tolerances(1e-6, 1e-8, 2, pilot, rerun);
  EXPECT_EQ(c.rtol, 1e-6);
  EXPECT_EQ(c.samples, (std::vector<std::uint64_t>{0, 1, 3}));
  EXPECT_NEAR(c.change[0], 0.03, 1e-15);
  EXPECT_EQ(c.change[1], 0.0) << "+inf against +inf agrees";
  EXPECT_NEAR(c.spread[0], std::sqrt(4.3), 1e-14);
  EXPECT_NEAR(c.spread[1], std::sqrt(2.0), 1e-14) << "the finite ones, 7 and 9";
  // 0.03 / 2.07 = 0.0145: enough. The second changed by 0: far tighter,
  // and the furthest step offered (100x looser).
  EXPECT_EQ(tolerance_verdict(c, 0).kind, ToleranceVerdict::Kind::enough);
  const ToleranceVerdict v = tolerance_verdict(c, 1);
  EXPECT_EQ(v.kind, ToleranceVerdict::Kind::far_tighter);
  EXPECT_EQ(v.factor, 100.0);
  EXPECT_NE(describe_verdict(c, 1).find("try rtol = 1e-04, atol = 1e-06 (100x looser"), std::string::npos)
      << describe_verdict(c, 1);
}

// A change of 0.5 of the spread: too loose; 0.01 / 0.5 = 0.02 -> the
// tolerances times 0.01 (a power of ten at or below).
TEST(ToleranceCheck, TooLooseSuggestsTighterTolerances) {
  const std::vector<double> pilot{0, 2, 0, 2};  // std 1.1547
  const std::vector<double> rerun{0.5774};
  const ToleranceCheck c = check_tolerances(1e-3, 1e-5, 1, pilot, rerun);
  const ToleranceVerdict v = tolerance_verdict(c, 0);
  EXPECT_EQ(v.kind, ToleranceVerdict::Kind::too_loose);
  EXPECT_NEAR(v.ratio, 0.5, 1e-4);
  EXPECT_EQ(v.factor, 0.01);
  EXPECT_NE(describe_verdict(c, 0).find("tighten [integrator] to rtol = 1e-05, atol = 1e-07"), std::string::npos)
      << describe_verdict(c, 0);
}

TEST(ToleranceCheck, NothingToSayWithoutSuccessfulRerunsOrSpread) {
  const ToleranceCheck failed = check_tolerances(1e-8, 1e-10, 1, {1, 2, 3}, {kNaN});
  EXPECT_TRUE(failed.samples.empty());
  EXPECT_EQ(tolerance_verdict(failed, 0).kind, ToleranceVerdict::Kind::unknown);
  EXPECT_NE(describe_verdict(failed, 0).find("not checked: no pilot sample succeeded"), std::string::npos);
  const ToleranceCheck flat = check_tolerances(1e-8, 1e-10, 1, {2, 2, 2}, {2});
  EXPECT_EQ(tolerance_verdict(flat, 0).kind, ToleranceVerdict::Kind::unknown);
  EXPECT_TRUE(check_tolerances(1e-8, 1e-10, 0, {}, {}).empty()) << "no responses, nothing to check";
}

TEST(ToleranceCheck, RoundTripsThroughItsCodec) {
  const ToleranceCheck c = check_tolerances(1e-7, 1e-9, 2, {1, 2, 3, 5, 4, 4}, {1.5, 2, 3, 5});
  std::vector<char> bytes;
  treedyn::ByteWriter out(bytes);
  c.write(out);
  treedyn::ByteReader in(bytes, "test");
  const ToleranceCheck back = ToleranceCheck::read(in);
  EXPECT_TRUE(in.done());
  EXPECT_EQ(back.rtol, c.rtol);
  EXPECT_EQ(back.atol, c.atol);
  EXPECT_EQ(back.samples, c.samples);
  EXPECT_EQ(back.change, c.change);
  EXPECT_EQ(back.spread, c.spread);
}

// Through the ensemble: the spherical pendulum's tip height after 2 s,
// integrated at rtol = atol = 1e-2 (far too loose: its change at 1e-4 is a
// large share of the spread the release angle gives), and at the job's
// 1e-10 / 1e-12 (far tighter than this answer needs). The warning comes at
// the pilot's end, the summary has the line, the file the group.
TEST(ToleranceCheckEnsemble, TooLooseIsWarnedAboutAndTightIsSaidToBe) {
  TempDir dir("tolerance_check");
  for (const bool loose : {true, false}) {
    std::string text = edited_job_text("spherical_pendulum.toml",
                                       {{"end_time = 10.0", "end_time = 2.0"}, {"samples = 64", "samples = 32"}});
    if (loose) {
      const std::size_t at = text.find("rtol = ");
      text.replace(at, text.find('\n', text.find("atol = ")) - at, "rtol = 1e-2\natol = 1e-2");
    }
    text +=
        "\n[[ensemble.response]]\nname = \"tip_height\"\nquantity = \"point_position\"\ncolumn = \"tip.z\"\n"
        "reduce = \"final\"\n";
    const fs::path job = dir.path() / (loose ? "loose.toml" : "tight.toml");
    write_text(job, text);
    const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", (dir.path() / "out.h5").string()},
                                        dir.path() / "capture");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (loose) {
      EXPECT_NE(r.err.find("warning: the integration is too loose for this answer"), std::string::npos) << r.err;
      EXPECT_NE(r.out.find("    integration: too loose for this answer: "), std::string::npos) << r.out;
      // The page says it too, in red, and the summary it writes again.
      const fs::path page = dir.path() / "page";
      const CommandResult report =
          run_command(TREEDYN_BINARY, {"report", (dir.path() / "out.h5").string(), "-o", page.string()},
                      dir.path() / "capture_report");
      ASSERT_EQ(report.exit_code, 0) << report.err;
      const std::string html = read_text(page / "index.html");
      EXPECT_NE(html.find("<div class=\"alarm\">tip_height: the integration is too loose for this answer: "),
                std::string::npos);
      EXPECT_NE(read_text(page / "summary.txt").find("    integration: too loose for this answer: "),
                std::string::npos);
    } else {
      EXPECT_EQ(r.err.find("warning: the integration"), std::string::npos) << r.err;
      EXPECT_NE(r.out.find("    integration: far tighter than this answer needs: "), std::string::npos) << r.out;
    }
    fs::remove(dir.path() / "out.h5");
  }
}

}  // namespace
