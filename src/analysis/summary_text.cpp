#include "analysis/summary_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/failure_region.hpp"

namespace treedyn::analysis {

std::string number(double v, const char* format) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

namespace {

std::string clipped(double v) { return number(std::clamp(v, 0.0, 1.0), "%.2g"); }

// "name 0.84 [0.61, 0.97]": an index with its interval, shown within [0, 1]
// (`index`), or a measure with its interval as it is.
std::string index_text(const std::string& name, double v, const double* ci, bool index) {
  std::string t = name + " " + number(v, index ? "%.2g" : "%.3g");
  if (ci && std::isfinite(ci[0]))
    t += " [" + (index ? clipped(ci[0]) : number(ci[0], "%.3g")) + ", " +
         (index ? clipped(ci[1]) : number(ci[1], "%.3g")) + "]";
  return t;
}

constexpr std::size_t kFailureShown = 3;  // inputs on a "what makes it exceed" line

// One unit of the failure region: its importance and, for a single input,
// where the failing runs put it (mean u, the design point).
std::string failure_unit_text(const EnsembleSpec& spec, const FailureRegion& region, std::size_t u) {
  std::string t = region.units[u].name + " " + number(region.unit_importance[u], "%.2f");
  if (region.units[u].inputs.size() != 1) return t + " (" + std::to_string(region.units[u].inputs.size()) + " inputs)";
  const unsigned i = region.units[u].inputs.front();
  return t + " (mean u " + number(region.mean_u[i], "%.2f") + ", design point " +
         number(region.design_point[i], "%.4g") + " " + spec.input_units()[i] + ")";
}

}  // namespace

void print_ranking(std::ostream& out, const std::vector<std::string>& names, const Ranking& ranking,
                   const std::vector<double>& measure, const std::vector<double>* ci, const char* samples_word,
                   const std::vector<bool>& hidden, bool indices) {
  std::vector<std::size_t> places;  // places in ranking.order of the units shown
  for (std::size_t k = 0; k < ranking.order.size(); ++k)
    if (hidden.empty() || !hidden[ranking.order[k]]) places.push_back(k);
  const std::size_t shown = std::min(places.size(), kRankedShown);
  std::string pending;
  for (std::size_t s = 0; s < shown; ++s) {
    const std::size_t u = ranking.order[places[s]];
    if (s > 0) {
      bool apart = false;
      for (std::size_t k = places[s - 1]; k < places[s]; ++k) apart = apart || ranking.told_apart(k);
      out << (apart ? " > " : " ~ ");
      if (!apart && pending.empty() && places[s] == places[s - 1] + 1 && std::isfinite(ranking.needed[places[s - 1]]))
        pending = "about " + number(ranking.needed[places[s - 1]], "%.0f") + " " + samples_word + " would tell " +
                  names[ranking.order[places[s - 1]]] + " from " + names[u];
    }
    out << index_text(names[u], measure[u], ci ? ci->data() + 2 * u : nullptr, indices);
  }
  if (places.size() > shown) out << " (and " << places.size() - shown << " more)";
  if (places.size() < ranking.order.size())
    out << " (not shown: " << ranking.order.size() - places.size() << " entries of lists, one by one)";
  out << "\n";
  if (ranking.resamples == 0)
    out << "      no bootstrap intervals: the order above is the point estimates' alone\n";
  else if (!pending.empty())
    out << "      ~: not told apart yet (95 % bootstrap interval of the difference holds 0); " << pending << "\n";
  if (ci && indices &&
      std::any_of(places.begin(), places.begin() + static_cast<std::ptrdiff_t>(shown), [&](std::size_t k) {
        const double v = measure[ranking.order[k]];
        return v < 0.0 || v > 1.0;
      }))
    out << "      an index estimated outside [0, 1] is noise of a small sample; its interval is shown within [0, 1]\n";
}

// The inputs the failing runs select on, by importance, and a warning for
// every input whose truncation bound holds most of them.
void print_failure_region(std::ostream& out, const EnsembleSpec& spec, const FailureRegion& region, const char* what) {
  if (region.runs == 0 || region.unit_importance.empty()) return;
  const std::size_t inputs = region.mean_u.size();
  out << "    what makes it exceed (" << region.runs << " " << what << "; importance):";
  if (std::none_of(region.unit_importance.begin(), region.unit_importance.end(),
                   [](double v) { return std::isfinite(v); }))
    out << " no input departs from its own distribution beyond chance";
  const Ranking order = rank_units(region.unit_importance, {}, region.runs);
  for (std::size_t k = 0; k < std::min(order.order.size(), kFailureShown); ++k) {
    if (!(region.unit_importance[order.order[k]] > 0.0)) break;
    out << (k ? "; " : " ") << failure_unit_text(spec, region, order.order[k]);
  }
  out << "\n";
  const double enough = static_cast<double>(std::max<std::uint64_t>(kFailureRegionRuns, inputs));
  if (region.effective_runs < enough)
    out << "      rough: " << region.runs << " runs beyond the limit"
        << (region.effective_runs < static_cast<double>(region.runs)
                ? " (as " + number(region.effective_runs, "%.0f") + " independent ones: chain states)"
                : std::string())
        << " for " << inputs << " inputs (chance alone moves each input's share; at least " << number(enough, "%.0f")
        << " would tell)\n";
  const std::vector<std::string> names = spec.input_names(), units = spec.input_units();
  for (std::size_t i = 0; i < inputs; ++i)
    if (region.near_bound[i] >= kBoundSetsProbability)
      out << "      warning: " << number(100.0 * region.near_bound[i], "%.0f") << " % of them have " << names[i]
          << " within " << number(100.0 * kNearBoundShare, "%.0f") << " % of its range of its bound "
          << number(region.bound[i], "%.6g") << " " << units[i]
          << ": P depends on where that distribution is cut off, not only on the dynamics\n";
}

}  // namespace treedyn::analysis
