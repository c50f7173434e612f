// Morris' lines in the end-of-run summary: the ranking by mu*, and which of
// the leading units act nonlinearly or through interactions (sigma at least
// mu*: their effects change sign or size across the grid).
#include <algorithm>
#include <string>

#include "analysis/summary_text.hpp"
#include "designs/morris/morris_answer.hpp"

namespace treedyn::designs {

void MorrisAnswer::print(std::ostream& out, const EnsembleSpec& spec, const Response& response) const {
  const MorrisIndices& m = indices;
  const std::vector<std::string> names = spec.unit_names();
  out << "    drivers (" << (spec.grouped ? "groups, " : "") << "Morris mu* [95 %], " << response.units
      << " per unit of u, from " << m.trajectories << " trajectories): ";
  analysis::print_ranking(out, names, m.ranking, m.mu_star, &m.mu_star_ci, "trajectories", {}, false);
  std::string nonlinear;
  for (std::size_t k = 0; k < std::min(m.ranking.order.size(), analysis::kRankedShown); ++k) {
    const std::size_t u = m.ranking.order[k];
    if (m.sigma[u] >= m.mu_star[u] && m.mu_star[u] > 0.0)
      nonlinear += (nonlinear.empty() ? "" : ", ") + names[u] + " (sigma " + analysis::number(m.sigma[u], "%.3g") + ")";
  }
  if (!nonlinear.empty()) out << "      sigma >= mu*, nonlinear or interacting: " << nonlinear << "\n";
}

}  // namespace treedyn::designs
