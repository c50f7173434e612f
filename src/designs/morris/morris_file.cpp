// Morris' answer in /sensitivity/<response>: morris_mu_star, morris_mu,
// morris_sigma (per unit), their _ci, morris_effects and morris_ranking.
#include <string>
#include <vector>

#include "designs/morris/morris_answer.hpp"

namespace treedyn::designs {

void MorrisAnswer::write(AnswerWriter& sg, const EnsembleSpec& spec, const Response& response) const {
  const MorrisIndices& m = indices;
  const std::string& response_units = response.units;
  const std::vector<std::string> units = spec.unit_names();
  const std::string per =
      " of each factor (an input, or a group moved together: see morris_unit_inputs); elementary effect EE = "
      "change of the response / its step in the inputs' probability u (radial: b - a, for a group the root mean "
      "square of its inputs'; trajectories: 1/2)";
  sg.per_unit("morris_mu_star", m.mu_star, response_units, "mean |EE| (Morris mu*, ranks the units)" + per, units);
  sg.per_unit("morris_mu", m.mu, response_units, "mean EE (its sign: the response's direction)" + per, units);
  sg.per_unit("morris_sigma", m.sigma, response_units,
              "standard deviation of EE (large: nonlinear or interacting)" + per, units);
  sg.intervals("morris_mu_star_ci", m.mu_star_ci, "95 % bootstrap interval of mu* (over trajectories)", units, "factor",
               response_units);
  sg.intervals("morris_mu_ci", m.mu_ci, "95 % bootstrap interval of mu (over trajectories)", units, "factor",
               response_units);
  sg.intervals("morris_sigma_ci", m.sigma_ci, "95 % bootstrap interval of sigma (over trajectories)", units, "factor",
               response_units);
  std::vector<double> counts(m.effects.begin(), m.effects.end());
  sg.per_unit("morris_effects", counts, "1",
              "elementary effects per unit (one per trajectory whose two runs "
              "of that step succeeded with finite values)",
              units);
  sg.attribute("morris_units", units);
  sg.attribute("morris_unit_inputs", spec.unit_inputs());
  sg.attribute("morris_trajectories", static_cast<long long>(m.trajectories));
  sg.attribute("morris_steps", std::string(spec.morris->radial ? "radial" : "trajectories"));
  if (!spec.morris->radial) sg.attribute("morris_levels", static_cast<long long>(spec.morris->levels));
  sg.ranking("morris_ranking", m.ranking, "Morris mu*", units, "trajectories");
}

}  // namespace treedyn::designs
