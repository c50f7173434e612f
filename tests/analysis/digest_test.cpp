// The end-of-run digest's first line: the rate divides the samples this run
// integrated itself by its time, so a resumed run (most samples restored)
// and a merge (none run) do not claim the restored ones.
#include "analysis/digest.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace {

std::string first_line(std::uint64_t ok, std::uint64_t failed, std::uint64_t run_here, double seconds) {
  treedyn::analysis::EnsembleDigest d;
  d.samples = ok + failed;
  d.ok = ok;
  d.failed = failed;
  d.ranks = 2;
  d.wall_seconds = seconds;
  d.run_here = run_here;
  std::ostringstream out;
  treedyn::analysis::print_digest(out, d);
  return out.str().substr(0, out.str().find('\n'));
}

TEST(Digest, RateCountsOnlyTheSamplesRunHere) {
  EXPECT_EQ(first_line(90, 10, 100, 4.0),
            "ensemble: 100 samples (90 ok, 10 failed) on 2 ranks in 4.00 s (25.00 samples/s)");
  // Resumed: 80 restored, 20 run in 4 s: 5 samples/s, not 25.
  EXPECT_EQ(first_line(100, 0, 20, 4.0),
            "ensemble: 100 samples (100 ok, 0 failed) on 2 ranks in 4.00 s (5.00 samples/s over the 20 run here; "
            "the others were restored from the checkpoint)");
  EXPECT_EQ(first_line(100, 0, 0, 0.5),
            "ensemble: 100 samples (100 ok, 0 failed) on 2 ranks in 0.50 s (none run here: merged or restored)");
}

}  // namespace
