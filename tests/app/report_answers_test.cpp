// The ensemble page's answers against the file they come from (issue 40,
// items 1-5): every ranking stated only as far as the bootstrap tells the
// inputs apart (as the text summary states it), the indices' verdict on N,
// what the failed runs change on the first screen, the index figures, the
// failure region with its truncation warning for Monte Carlo and subset
// simulation, one voice on a subset-simulation page, and units on values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

const std::string kPython = "/usr/bin/python3";
const std::string kChecks = std::string(TREEDYN_TEST_SUPPORT_DIR) + "/report_checks.py";

// What the page's HTML makes of a text (page.py escapes with html.escape).
std::string escaped(const std::string& text) {
  std::string out;
  // clang-format off
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '\'') out += "&#x27;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  // clang-format on
  return out;
}

std::string formatted(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

double group_double(hid_t file, const std::string& group, const std::string& name) {
  const Hid g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose);
  return read_double_attribute(g.get(), name).at(0);
}

long long group_integer(hid_t file, const std::string& group, const std::string& name) {
  const Hid g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose);
  return read_integer_attribute(g.get(), name);
}

std::string group_string(hid_t file, const std::string& group, const std::string& name) {
  const Hid g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose);
  return read_single_string_attribute(g.get(), name);
}

struct Report {
  std::string page, summary;
};

class ReportAnswers : public ::testing::Test {
 protected:
  fs::path run(const std::string& name, const std::string& text) {
    const fs::path job = dir_.path() / (name + ".toml"), out = dir_.path() / (name + ".h5");
    write_text(job, text);
    const CommandResult r = run_ensemble(2, job, out, dir_.path() / ("capture_" + name));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }
  Report report(const fs::path& out) {
    const fs::path page = dir_.path() / (out.stem().string() + "_report");
    const CommandResult r =
        run_command(TREEDYN_BINARY, {"report", out.string(), "-o", page.string()}, dir_.path() / "capture_report");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const CommandResult png = run_command(kPython, {kChecks, "pngs", page.string()}, dir_.path() / "capture_pngs");
    EXPECT_EQ(png.exit_code, 0) << png.out << png.err;
    return {read_text(page / "index.html"), read_text(page / "summary.txt")};
  }
  TempDir dir_{"report_answers_test"};
};

// The summary's ranking of `response` ("A 0.88 [0.53, 1] > B 0.23 [0.022, 0.44] ~ C ..."), up to its first
// unit whose interval ends below 0.05 (the page names those "matter little" instead).
std::string summary_ranking(const std::string& summary, const std::string& response) {
  const std::size_t at = summary.find("  " + response + " (");
  const std::size_t line = summary.find("    drivers (", at);
  const std::size_t start = summary.find("): ", line) + 3, end = summary.find('\n', start);
  const std::string ranking = summary.substr(start, end - start);
  static const std::regex unit(R"((^| [>~] )(.+?) (\S+) \[(\S+), (\S+)\])");
  std::string prefix;
  for (auto it = std::sregex_iterator(ranking.begin(), ranking.end(), unit); it != std::sregex_iterator(); ++it) {
    if (std::stod((*it)[5]) < 0.05) break;
    prefix += (*it)[0];
  }
  return prefix;
}

// The crane example: the first screen answers P, which input matters and
// whether N is enough (for the indices too), and the page states each
// ranking as the summary does, with one note where the rank measure puts
// another input first.
TEST_F(ReportAnswers, CraneExampleFirstScreenMatchesTheFileAndTheSummary) {
  if (const std::string why = skipped_when_sanitized("crane_payload", true); !why.empty()) GTEST_SKIP() << why;
  const fs::path out = run("crane", read_text(fs::path(TREEDYN_JOBS_DIR) / "crane_payload.toml"));
  const Report r = report(out);
  H5File f(out);
  const std::size_t first_figure = r.page.find("<img");
  for (const std::string& name : read_string_attribute(f.id(), "/samples/responses", "columns")) {
    SCOPED_TRACE(name);
    const std::string s = "/sensitivity/" + name;
    // The green box states the summary's ranking, in its order, with its > and ~, before any figure.
    const std::size_t box = r.page.find("<div class=\"good\">" +
                                        escaped(name + " is driven by " + summary_ranking(r.summary, name) + " ("));
    EXPECT_NE(box, std::string::npos) << summary_ranking(r.summary, name) << "\n" << r.summary;
    EXPECT_LT(box, first_figure);
    // The indices' verdict on N, from the attributes.
    const std::string verdict = "the widest total-index interval of an input that matters is " +
                                formatted("%.2g", group_double(f.id(), s, "index_widest_interval")) + " (" +
                                group_string(f.id(), s, "index_widest_unit") + ")";
    EXPECT_NE(r.page.find(escaped(verdict)), std::string::npos) << verdict;
    const std::string says = group_integer(f.id(), s, "indices_enough")
                                 ? "yes: " + escaped(verdict)
                                 : "not for 0.1: " + escaped(verdict) + "; about " +
                                       formatted("%.0f", group_double(f.id(), s, "index_base_points_needed")) +
                                       " base points would do";
    EXPECT_NE(r.page.find(says), std::string::npos) << says;
    EXPECT_NE(r.page.find("<img src=\"sobol_indices_" + name + ".png\""), std::string::npos);
  }
  // 67 inputs and 32 A and B runs: no rank regression, and no empty SRRC map.
  EXPECT_NE(r.page.find("No SRRC map: the rank regression needs more runs than inputs (67 inputs, 32 runs)."),
            std::string::npos);
  // peak_tension's failure region: its table, rough (few runs for 67 inputs).
  const long long runs = group_integer(f.id(), "/responses/peak_tension/exceedance/failure_region", "runs");
  ASSERT_GT(runs, 0);
  EXPECT_NE(r.page.find("peak_tension: the " + std::to_string(runs) + " counted runs beyond the limit"),
            std::string::npos);
  EXPECT_NE(r.page.find("Rough: " + std::to_string(runs) + " runs beyond the limit for 67 inputs"), std::string::npos);
  EXPECT_NE(r.page.find("<img src=\"failure_region_peak_tension.png\""), std::string::npos);
  // The largest peak tension over every run (an AB run) is in the extremes table with its unit.
  const DoubleArray values = read_double_array(f.id(), "/samples/responses");  // peak_tension: column 0
  const std::vector<long long> status = read_integers(f.id(), "/samples/status");
  double largest = -INFINITY;
  for (std::size_t k = 0; k < status.size(); ++k)
    if (status[k] == 0) largest = std::max(largest, values(k, 0));
  EXPECT_NE(r.page.find("<td>" + formatted("%.6g", largest) + " N</td>"), std::string::npos) << largest;
  EXPECT_EQ(r.page.find("for a smaller P use subset simulation"), std::string::npos);
}

// max_steps = 60: some runs fail. The red banner, before the answers'
// table, says what P is with the failed runs counted either way and how
// many base points the indices rest on; unreliable indices are no green box.
TEST_F(ReportAnswers, FailuresOnTheFirstScreen) {
  if (const std::string why = skipped_when_sanitized("crane_payload", true); !why.empty()) GTEST_SKIP() << why;
  const fs::path out =
      run("crane_failing", edited_job_text("crane_payload.toml", {{"rtol = 1e-8", "rtol = 1e-8\nmax_steps = 60"}}));
  const Report r = report(out);
  H5File f(out);
  const std::string e = "/responses/peak_tension/exceedance";
  const long long failed = read_integers(f.id(), e + "/failed").at(0);
  const long long successful = read_integers(f.id(), e + "/successful").at(0);
  ASSERT_GT(failed, 0) << "the counted runs must include failed ones";
  const std::vector<double> bounds = read_doubles(f.id(), e + "/with_failed");
  const std::size_t banner = r.page.find("<div class=\"alarm\">");
  ASSERT_NE(banner, std::string::npos);
  EXPECT_LT(banner, r.page.find("<table"));
  const std::string p = "rests on " + std::to_string(successful) + " of " + std::to_string(successful + failed) +
                        " counted runs; with the " + std::to_string(failed) +
                        " failed ones counted as not exceeding or as exceeding it would be " +
                        formatted("%.4g", bounds[0]) + " to " + formatted("%.4g", bounds[1]) + ".";
  EXPECT_NE(r.page.find(p, banner), std::string::npos) << p;
  EXPECT_LT(r.page.find(p, banner), r.page.find("</div>", banner));
  const std::string s = "/sensitivity/peak_tension";
  const long long base = group_integer(f.id(), s, "sobol_base_samples"),
                  blocks = group_integer(f.id(), s, "sobol_blocks");
  ASSERT_LT(base, blocks);
  const bool reliable = group_integer(f.id(), s, "sobol_reliable") != 0;
  EXPECT_NE(r.page.find("The Sobol&#x27; indices rest on " + std::to_string(base) + " of " + std::to_string(blocks) +
                            " base points (a base point counts when all its 6 runs succeeded)" +
                            (reliable ? "." : "; unreliable: fewer than 80 %."),
                        banner),
            std::string::npos);
  if (!reliable) {
    EXPECT_EQ(r.page.find("<div class=\"good\">peak_tension is driven by"), std::string::npos);
    EXPECT_NE(r.page.find("<div class=\"alarm\">Unreliable: failed runs left " + std::to_string(base) + " of " +
                          std::to_string(blocks) + " base points complete"),
              std::string::npos);
    EXPECT_NE(r.page.find("no: unreliable, failed runs left"), std::string::npos) << "the verdict on N says so too";
  }
}

// The kicked ball of tests/mpi/failure_region_test.cpp: a final energy of
// E0 + 0.275 |w|^2 with the kick(s) random; `inputs` are the perturbation
// tables, `design` goes into [ensemble].
std::string ball_job(const std::string& design, const std::string& inputs, double limit, bool with_limit = true) {
  return ball_job_text("seed = 5\n" + design,
                       inputs + normal_input("base.position.x", 0.5) +
                           energy_response(with_limit ? std::optional<double>(limit) : std::nullopt));
}

const std::string kTwoKicks = R"(
[[ensemble.perturbation]]
target = "body.ball.angular_velocity.x"
distribution = "normal"
std = 1.0

[[ensemble.perturbation]]
target = "body.ball.angular_velocity.y"
distribution = "normal"
std = 0.7
)";

// Two kicks whose total indices are 0.81 and 0.19 (variances 2 and
// 2 x 0.7^4 of the squares): at 8 base points the bootstrap does not yet
// tell them apart and the page says how many would; at 256 it states the
// order and calls the input that changes nothing negligible.
TEST_F(ReportAnswers, ARankingIsStatedOnlyOnceTheDataTellTheInputsApart) {
  const std::string x = "body.ball.angular_velocity.x", y = "body.ball.angular_velocity.y";
  for (const int n : {8, 256}) {
    SCOPED_TRACE(n);
    const fs::path out =
        run("ball_" + std::to_string(n),
            ball_job("samples = " + std::to_string(n) + "\ndesign = \"saltelli\"", kTwoKicks, 0.0, false));
    const Report r = report(out);
    H5File f(out);
    const std::vector<long long> order = read_integers(f.id(), "/sensitivity/energy/sobol_ranking/order");
    const std::vector<long long> apart = read_integers(f.id(), "/sensitivity/energy/sobol_ranking/told_apart");
    ASSERT_EQ(order.at(0), 0) << "the stronger kick first";
    ASSERT_EQ(order.at(1), 1);
    EXPECT_EQ(apart.at(0), n == 8 ? 0 : 1);
    const std::size_t box = r.page.find("<div class=\"good\">energy is driven by " + x);
    ASSERT_NE(box, std::string::npos);
    const std::string sentence = r.page.substr(box, r.page.find("</div>", box) - box);
    if (n == 8) {
      const double needed = read_doubles(f.id(), "/sensitivity/energy/sobol_ranking/needed").at(0);
      EXPECT_NE(sentence.find(" ~ " + y), std::string::npos) << sentence;
      EXPECT_NE(sentence.find(x + " and " + y + " cannot yet be told apart (about " + formatted("%.0f", needed) +
                              " base points would tell them apart)."),
                std::string::npos)
          << sentence;
      EXPECT_NE(r.summary.find(" ~ " + y), std::string::npos) << r.summary;
    } else {
      EXPECT_NE(sentence.find(" &gt; " + y), std::string::npos) << sentence;
      EXPECT_EQ(sentence.find("cannot yet be told apart"), std::string::npos) << sentence;
      EXPECT_NE(sentence.find("base.position.x matters little"), std::string::npos) << sentence;
      EXPECT_NE(r.summary.find(" > " + y), std::string::npos) << r.summary;
    }
  }
}

// A kick truncated at 1.02 a above (and far below): the runs beyond |w_x|
// = a lie within 1 % of the range of the upper bound, which sets P. For
// subset simulation the page warns as for Monte Carlo, takes the region
// of every level, colours its scatter plots by level and gives no
// Monte-Carlo-only sentence.
TEST_F(ReportAnswers, ATruncationBoundThatSetsPIsWarnedAboutOnASubsetSimulationPage) {
  if (const std::string why = skipped_when_sanitized_as_large("subset simulation's page"); !why.empty())
    GTEST_SKIP() << why;
  const double a = 3.0, upper = 1.02 * a;
  const std::string kick =
      "\n[[ensemble.perturbation]]\ntarget = \"body.ball.angular_velocity.x\"\n"
      "distribution = \"truncated_normal\"\nmean = 0.0\nstd = 1.0\nlower = -1.0\nupper = " +
      formatted("%.6f", upper) + "\n";
  const fs::path out =
      run("truncated", ball_job("samples = 500\n" + kBallSubset, kick, kBallE0 + kBallHalfInertia * a * a));
  const Report r = report(out);
  H5File f(out);
  const std::string g = "/rare_event/energy/failure_region";
  const long long runs = group_integer(f.id(), g, "runs");
  ASSERT_GT(runs, 0);
  const double near = read_doubles(f.id(), g + "/near_bound").at(0);
  ASSERT_GE(near, 0.5);
  const std::string warning = formatted("%.0f", 100 * near) +
                              " % of the failing runs have body.ball.angular_velocity.x "
                              "within 1 % of its upper bound " +
                              formatted("%.6g", read_doubles(f.id(), g + "/bound").at(0)) +
                              " rad/s: P depends on where that distribution is cut off";
  EXPECT_NE(r.page.find("<div class=\"warning\">" + warning), std::string::npos) << warning;
  EXPECT_NE(r.page.find("energy: the " + std::to_string(runs) +
                        " runs beyond the limit, any level of the subset "
                        "simulation"),
            std::string::npos);
  EXPECT_NE(r.page.find("coloured by level"), std::string::npos);
  EXPECT_NE(r.page.find("the subset simulation&#x27;s, above (level 0 alone is not the answer)"), std::string::npos);
  for (const char* monte_carlo_only :
       {"for a smaller P use subset simulation", "no exceedance in", "no successful run exceeds the limit"})
    EXPECT_EQ(r.page.find(monte_carlo_only), std::string::npos) << monte_carlo_only;
  EXPECT_LT(r.page.find("<h2>Answers</h2>"), r.page.find("Rare event (subset simulation)"));
}

// A limit no successful run exceeds while some runs failed (masses <= 0 are
// invalid models): one line, no table of NaN; a response without a limit
// gets nothing in the failure region's section.
TEST_F(ReportAnswers, NoExceedingRunIsOneLineAndNoLimitIsNothing) {
  const std::string inputs =
      "\n[[ensemble.perturbation]]\ntarget = \"body.ball.angular_velocity.x\"\n"
      "distribution = \"normal\"\nstd = 1.0\n"
      "\n[[ensemble.perturbation]]\ntarget = \"body.ball.mass\"\ndistribution = \"normal\"\n"
      "mean = 1.0\nstd = 0.5\n";
  std::string text = ball_job("samples = 200\ndesign = \"monte_carlo\"", inputs, 1e6);
  text += "\n[[ensemble.response]]\nname = \"spin\"\nquantity = \"energy\"\ncolumn = \"kinetic\"\nreduce = \"max\"\n";
  const fs::path out = run("none", text);
  const Report r = report(out);
  H5File f(out);
  const long long failed = read_integers(f.id(), "/responses/energy/exceedance/failed").at(0);
  ASSERT_GT(failed, 0);
  EXPECT_NE(r.page.find("<p>energy: no successful run exceeds the limit; " + std::to_string(failed) +
                        " failed runs might have.</p>"),
            std::string::npos);
  const std::size_t section = r.page.find("What makes each response exceed its limit");
  ASSERT_NE(section, std::string::npos);
  const std::size_t next = std::min(r.page.find("<h3>", section), r.page.find("<figure", section));
  const std::string part = r.page.substr(section, next - section);
  EXPECT_EQ(part.find("<th>importance</th>"), std::string::npos) << part;
  EXPECT_EQ(part.find("spin"), std::string::npos) << part;
  EXPECT_EQ(part.find("nan"), std::string::npos) << part;
  // The failed runs' reasons, a string dataset (bytes in h5py 3), decoded on the page.
  const std::vector<long long> status = read_integers(f.id(), "/samples/status");
  const std::size_t invalid = std::find(status.begin(), status.end(), 2) - status.begin();
  ASSERT_LT(invalid, status.size());
  const std::string reason = read_strings(f.id(), "/samples/reason").at(invalid);
  ASSERT_FALSE(reason.empty());
  EXPECT_NE(r.page.find("<td>" + escaped(reason) + "</td>"), std::string::npos) << reason;
  // No bytes' repr (b'...') anywhere: "b'" at the start of a word.
  for (std::size_t at = r.page.find("b&#x27;"); at != std::string::npos; at = r.page.find("b&#x27;", at + 1))
    EXPECT_TRUE(at > 0 && std::isalpha(static_cast<unsigned char>(r.page[at - 1]))) << r.page.substr(at - 40, 80);
}

// The crane example as a Morris screen: the page ranks by mu* as the
// summary does, with its table and its mu*-sigma figure
// (tests/report/morris_page_checks.py); a Saltelli page has none of it.
TEST_F(ReportAnswers, MorrisScreenRanksByMuStarWithItsTableAndFigure) {
  if (const std::string why = skipped_when_sanitized("crane_payload", true); !why.empty()) GTEST_SKIP() << why;
  const std::string checks = std::string(TREEDYN_TEST_SUPPORT_DIR) + "/../report/morris_page_checks.py";
  const std::string job = edited_job_text("crane_payload.toml", {{"\nsamples = 16\n", "\n"},
                                                                 {"design = \"saltelli\"", "design = \"morris\""}}) +
                          "\n[ensemble.morris]\ntrajectories = 10\n";
  for (const fs::path& out : {run("crane_morris", job),
                              run("crane_saltelli", read_text(fs::path(TREEDYN_JOBS_DIR) / "crane_payload.toml"))}) {
    SCOPED_TRACE(out.string());
    report(out);
    const CommandResult c =
        run_command(kPython, {checks, out.string(), (dir_.path() / (out.stem().string() + "_report")).string()},
                    dir_.path() / "capture_morris");
    EXPECT_EQ(c.exit_code, 0) << c.out << c.err;
  }
}

}  // namespace
