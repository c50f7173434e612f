// Split and merge: `--samples FIRST:END` parts on different rank counts,
// merged by `treedyn-ensemble merge`, are bitwise one run over the union in
// /stats, /samples, /responses and /sensitivity. Overlapping parts, parts of
// another job and bad ranges are refused (exit 2); an incomplete set merges,
// and the file says which samples it holds.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

namespace fs = std::filesystem;
using namespace treedyn::testing;

// The shipped Kapitza job (Sobol design, two responses) cut to 48 samples
// and 1 s of motion.
std::string job_text(const std::string& seed = "seed = 5") {
  return edited_job_text(
      "kapitza.toml",
      {{"samples = 128", "samples = 48\npilot_samples = 8"}, {"seed = 5", seed}, {"end_time = 5.0", "end_time = 1.0"}});
}

CommandResult merge(const std::vector<std::string>& parts, const fs::path& out, const fs::path& capture) {
  std::vector<std::string> args = {"merge", "-o", out.string()};
  args.insert(args.end(), parts.begin(), parts.end());
  return run_command(TREEDYN_ENSEMBLE_BINARY, args, capture, {"timeout", "120"});
}

class Merge : public ::testing::Test {
 protected:
  void SetUp() override {
    job_ = dir_.path() / "kapitza.toml";
    write_text(job_, job_text());
    reference_ = dir_.path() / "reference.h5";
    const auto r = run_ensemble(2, job_, reference_, capture());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  // One part, under mpirun with `ranks` ranks (0: alone).
  fs::path part(int ranks, const std::string& range) {
    const fs::path out = dir_.path() / ("part_" + range.substr(0, range.find(':')) + ".part");
    const auto r = run_ensemble(ranks, job_, out, capture(), {"--samples", range});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }
  fs::path capture() const { return dir_.path() / "capture"; }

  TempDir dir_{"merge_test"};
  fs::path job_, reference_;
};

TEST_F(Merge, ThreePartsOnDifferentRankCountsMergeIntoOneRunBitwise) {
  // The first part holds the pilot samples and more; the others need them
  // for the calibration only.
  const fs::path a = part(2, "0:20"), b = part(3, "20:33"), c = part(0, "33:48");
  const fs::path merged = dir_.path() / "merged.h5";
  const auto r = merge({c.string(), a.string(), b.string()}, merged, capture());  // any order
  std::printf("[merge] exit %d: %s%s", r.exit_code, r.out.c_str(), r.err.c_str());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File ref(reference_), got(merged);
  ASSERT_TRUE(ref.ok() && got.ok());
  expect_identical_datasets(ref.id(), "one run", got.id(), "merged parts",
                            {"/stats", "/samples", "/responses", "/sensitivity", "/nominal", "/integration_check"});
  EXPECT_EQ(read_integer_attribute(got.id(), "samples"), 48);
  EXPECT_EQ(read_double_attribute(got.id(), "held_samples"), (std::vector<double>{0, 48}));
  EXPECT_EQ(read_string_attribute(got.id(), "merged_from").size(), 3u);
  // Provenance: the job the parts ran, the merge's own time, no sample run by the merge itself.
  EXPECT_EQ(read_single_string_attribute(got.id(), "job_path"), fs::absolute(job_).lexically_normal().string());
  const double wall = read_double_attribute(got.id(), "wall_time_seconds").at(0);
  EXPECT_GT(wall, 0.0);
  EXPECT_EQ(read_integer_attribute(got.id(), "samples_run_here"), 0);
  // The merge's writing of the parts' 48 records, a part of its own time.
  const std::vector<double> writing = read_double_attribute(got.id(), "record_writing_seconds_per_rank");
  ASSERT_EQ(writing.size(), 1u);
  EXPECT_GT(writing[0], 0.0);
  EXPECT_LT(writing[0], wall);
}

TEST_F(Merge, OverlapsOtherJobsAndBadRangesAreRefusedAndGapsAreReported) {
  const fs::path a = part(2, "0:20"), b = part(0, "15:30"), c = part(0, "40:48");
  // Overlap.
  auto r = merge({a.string(), b.string()}, dir_.path() / "x.h5", capture());
  std::printf("[overlap] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("overlap"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_.path() / "x.h5"));
  // Another job.
  const fs::path other_job = dir_.path() / "other.toml";
  write_text(other_job, job_text("seed = 6"));
  const fs::path other = dir_.path() / "other.part";
  ASSERT_EQ(run_ensemble(0, other_job, other, capture(), {"--samples", "20:40"}).exit_code, 0);
  r = merge({a.string(), other.string()}, dir_.path() / "x.h5", capture());
  std::printf("[another job] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("another job file"), std::string::npos) << r.err;
  // Not a part file.
  r = merge({reference_.string()}, dir_.path() / "x.h5", capture());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not a treedyn checkpoint"), std::string::npos) << r.err;
  // Damaged: cut in half, or one byte changed.
  {
    std::string bytes = read_text(a);
    const fs::path cut = dir_.path() / "cut.part", flipped = dir_.path() / "flipped.part";
    write_text(cut, bytes.substr(0, bytes.size() / 2));
    bytes[bytes.size() / 3] ^= 0x5a;
    write_text(flipped, bytes);
    for (const fs::path& bad : {cut, flipped}) {
      r = merge({bad.string()}, dir_.path() / "x.h5", capture());
      std::printf("[damaged part] exit %d: %s", r.exit_code, r.err.c_str());
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find("is damaged"), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(dir_.path() / "x.h5"));
      EXPECT_FALSE(fs::exists(dir_.path() / "x.h5.lock")) << "a refused merge leaves no lock";
    }
    // The advice followed: the damaged part (a's range, 0:20) run again into
    // the path it names, and the merge works.
    EXPECT_NE(r.err.find("run that part again with its --samples range (into `" + flipped.string() + "`)"),
              std::string::npos)
        << r.err;
    ASSERT_EQ(run_ensemble(0, job_, flipped, capture(), {"--samples", "0:20"}).exit_code, 0);
    r = merge({flipped.string(), c.string()}, dir_.path() / "x.h5", capture());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    fs::remove(dir_.path() / "x.h5");
  }
  // Bad ranges.
  for (const char* range : {"30:20", "0:49", "a:b", "5"}) {
    const auto bad = run_ensemble(0, job_, dir_.path() / "bad.part", capture(), {"--samples", range});
    std::printf("[--samples %s] exit %d: %s", range, bad.exit_code, bad.err.c_str());
    EXPECT_EQ(bad.exit_code, 2) << range;
    EXPECT_NE(bad.err.find("--samples"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir_.path() / "bad.part"));
  }
  // A gap (20 .. 39 missing): merged, with a note and the held ranges.
  const fs::path merged = dir_.path() / "partial.h5";
  r = merge({a.string(), c.string()}, merged, capture());
  std::printf("[incomplete] exit %d: %s", r.exit_code, r.err.c_str());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("hold 28 of 48 samples"), std::string::npos) << r.err;
  H5File got(merged);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(read_double_attribute(got.id(), "held_samples"), (std::vector<double>{0, 20, 40, 48}));
  const auto status = read_integers(got.id(), "/samples/status");
  ASSERT_EQ(status.size(), 48u);
  for (std::size_t k = 0; k < 48; ++k) EXPECT_EQ(status[k] == 3, k >= 20 && k < 40) << "sample " << k;
  EXPECT_FALSE(exists(got.id(), "/responses")) << "answers need every sample";
}

}  // namespace
