#include "analysis/ranking_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace treedyn::ensemble {

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

}  // namespace treedyn::ensemble
