#include "analysis/digest.hpp"

#include <algorithm>
#include <cstdio>

namespace treedyn::analysis {
namespace {

std::string format(const char* pattern, double a, double b, double c, double d) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c, d);
  return buffer;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> digest_columns(const ColumnLayout& layout, int bodies) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  auto add = [&](const char* quantity, std::size_t first, std::size_t count) {
    for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
      if (layout.quantity[q] != quantity) continue;
      for (std::size_t k = first; k < std::min(first + count, layout.names[q].size()); ++k) out.emplace_back(q, k);
    }
  };
  add("point_position", 0, 3);
  add("com_position", 3 * (static_cast<std::size_t>(bodies) - 1), 3);
  add("energy", 3, 1);
  return out;
}

EnsembleDigest digest_of(const Job& job, const EnsembleSpec& spec, const statistics::EnsembleStatistics& s,
                         const ensemble::RunSummary& summary) {
  const ColumnLayout layout = column_layout(job.model, job.output);
  const std::size_t last = job.request.output_times.size() - 1;
  EnsembleDigest d;
  d.samples = summary.samples_used > 0 ? summary.samples_used : spec.runs;
  d.ok = summary.ok;
  d.failed = summary.failed;
  d.ranks = summary.ranks;
  d.wall_seconds = summary.wall_seconds;
  d.run_here = summary.samples_run_here();
  d.last_time = job.request.output_times[last];
  d.low_probability = *std::min_element(spec.quantiles.begin(), spec.quantiles.end());
  d.high_probability = *std::max_element(spec.quantiles.begin(), spec.quantiles.end());
  for (auto [q, k] : digest_columns(layout, job.model.n)) {
    const std::size_t e = last * layout.columns + layout.offset[q] + k;
    d.lines.push_back({layout.quantity[q], layout.names[q][k], s.mean(e), s.std_dev(e),
                       s.quantile(e, d.low_probability), s.quantile(e, d.high_probability)});
  }
  return d;
}

void print_digest(std::ostream& out, const EnsembleDigest& d) {
  char line[200];
  std::snprintf(line, sizeof line, "ensemble: %llu samples (%llu ok, %llu failed) on %d rank%s in %.2f s",
                static_cast<unsigned long long>(d.samples), static_cast<unsigned long long>(d.ok),
                static_cast<unsigned long long>(d.failed), d.ranks, d.ranks == 1 ? "" : "s", d.wall_seconds);
  out << line;
  const double rate = d.wall_seconds > 0 ? static_cast<double>(d.run_here) / d.wall_seconds : 0.0;
  if (d.run_here >= d.ok + d.failed)
    out << format(" (%.2f samples/s)\n", rate, 0.0, 0.0, 0.0);
  else if (d.run_here == 0)
    out << " (none run here: merged or restored)\n";
  else
    out << format(" (%.2f samples/s over the %g run here; the others were restored from the checkpoint)\n", rate,
                  static_cast<double>(d.run_here), 0.0, 0.0);
  if (d.ok == 0) return;
  out << format("at t = %g s: mean +- std [%g%%, %g%%]\n", d.last_time, 100.0 * d.low_probability,
                100.0 * d.high_probability, 0.0);
  for (const DigestLine& l : d.lines) {
    std::snprintf(line, sizeof line, "  %-16s %-18s ", l.quantity.c_str(), l.column.c_str());
    out << line << format("% .6g +- %.3g  [% .6g, % .6g]\n", l.mean, l.std, l.low, l.high);
  }
}

}  // namespace treedyn::analysis
