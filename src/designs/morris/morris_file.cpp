#include "designs/morris/morris_file.hpp"

#include <string>
#include <vector>

#include "hdf5/answer_datasets.hpp"
#include "hdf5/described.hpp"

namespace treedyn::designs {

using answers_file::write_interval_matrix;  // the datasets every design's answers are written with
using answers_file::write_per_input;
using answers_file::write_ranking;

void write_morris(hid_t sg, const ensemble::EnsembleSpec& spec, const MorrisIndices& m,
                  const std::string& response_units) {
  const std::vector<std::string> units = spec.unit_names();
  const std::string per =
      " of each factor (an input, or a group moved together: see morris_unit_inputs); elementary effect EE = "
      "change of the response / its step in the inputs' probability u (radial: b - a, for a group the root mean "
      "square of its inputs'; trajectories: 1/2)";
  write_per_input(sg, "morris_mu_star", m.mu_star, response_units, "mean |EE| (Morris mu*, ranks the units)" + per,
                  units);
  write_per_input(sg, "morris_mu", m.mu, response_units, "mean EE (its sign: the response's direction)" + per, units);
  write_per_input(sg, "morris_sigma", m.sigma, response_units,
                  "standard deviation of EE (large: nonlinear or interacting)" + per, units);
  write_interval_matrix(sg, "morris_mu_star_ci", m.mu_star_ci, "95 % bootstrap interval of mu* (over trajectories)",
                        units, "factor", response_units);
  write_interval_matrix(sg, "morris_mu_ci", m.mu_ci, "95 % bootstrap interval of mu (over trajectories)", units,
                        "factor", response_units);
  write_interval_matrix(sg, "morris_sigma_ci", m.sigma_ci, "95 % bootstrap interval of sigma (over trajectories)",
                        units, "factor", response_units);
  std::vector<double> counts(m.effects.begin(), m.effects.end());
  write_per_input(sg, "morris_effects", counts, "1",
                  "elementary effects per unit (one per trajectory whose two runs "
                  "of that step succeeded with finite values)",
                  units);
  h5::write_attribute(sg, "morris_units", units);
  h5::write_attribute(sg, "morris_unit_inputs", spec.unit_inputs());
  h5::write_attribute(sg, "morris_trajectories", static_cast<long long>(m.trajectories));
  h5::write_attribute(sg, "morris_steps", std::string(spec.morris->radial ? "radial" : "trajectories"));
  if (!spec.morris->radial) h5::write_attribute(sg, "morris_levels", static_cast<long long>(spec.morris->levels));
  write_ranking(sg, "morris_ranking", m.ranking, "Morris mu*", units, "trajectories");
}

}  // namespace treedyn::designs
