// The end-of-run summary of an ensemble, as data: what treedyn-ensemble
// prints when it finishes and what `treedyn report` prints from the file are
// this one structure and one printer (the report fills it from /stats and
// /responses, the ensemble from its accumulators).
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/answers.hpp"
#include "ensemble/run_summary.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace treedyn::analysis {

struct DigestLine {
  std::string quantity, column;
  double mean = 0.0, std = 0.0, low = 0.0, high = 0.0;  // at the last output time
};

struct EnsembleDigest {
  std::uint64_t samples = 0, ok = 0, failed = 0;
  int ranks = 1;
  double wall_seconds = 0.0;
  // Samples this run integrated itself: fewer than ok + failed after a resume
  // (the rest restored) or a merge (none); the rate divides these by the time.
  std::uint64_t run_here = 0;
  double last_time = 0.0;
  double low_probability = 0.05, high_probability = 0.95;  // the outer stored quantiles
  std::vector<DigestLine> lines;
};

// The telling columns of a layout: (quantity index, column index) of the
// first recorded point, the last body's centre of mass and the total energy.
std::vector<std::pair<std::size_t, std::size_t>> digest_columns(const ColumnLayout& layout, int bodies);

// The digest of a finished run, from its accumulated statistics.
EnsembleDigest digest_of(const Job& job, const EnsembleSpec& spec, const statistics::EnsembleStatistics& stats,
                         const ensemble::RunSummary& summary);

void print_digest(std::ostream& out, const EnsembleDigest& digest);

}  // namespace treedyn::analysis
