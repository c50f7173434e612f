// Morris' screening measures of one response from its elementary effects,
// per factor g (an input, or a group moved together):
//   radial (default): EE_g(t) = (f(A_t with g from B_t) - f(A_t)) / step,
//     step = b - a for a single input, the root mean square of its inputs'
//     b - a for a group (whose sign then says nothing);
//   trajectories: EE_g(t) = d (f(x_s) - f(x_{s-1})) / Delta for the step s
//     that moved g, d = +1 up or -1 down, Delta = 1/2 in u
//     (morris_points.hpp).
// mu_g their mean, mu*_g the mean of |EE_g| (Campolongo et al. 2007: it
// ranks like the total Sobol' index), sigma_g their standard deviation
// (n - 1; large: the input acts through interactions or nonlinearly).
// Units: the response's per unit of u, so for an input uniform on [a, b]
// and f = c x, EE = c (b - a) exactly in either variant.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "analysis/ranking.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

struct MorrisIndices {
  std::vector<double> mu, mu_star, sigma;           // per unit; NaN without effects (sigma: fewer than 2)
  std::vector<double> mu_ci, mu_star_ci, sigma_ci;  // per unit: 95 % bootstrap interval, low and high
  std::vector<std::uint64_t> effects;               // per unit: the elementary effects behind them
  std::uint64_t trajectories = 0;                   // rows of effects (trajectories run)
  analysis::Ranking ranking;                        // by mu*, the bootstrap over trajectories
};

// `effects`: T rows (trajectories) x `units`, row-major, NaN where a run of
// the step failed or its value is not finite. The intervals are percentile
// intervals of `resamples` bootstrap resamplings of the T trajectories,
// drawn from a counter-based generator keyed by `seed` (reproducible).
MorrisIndices morris_indices(std::span<const double> effects, std::size_t units, int resamples, std::uint64_t seed);

// The elementary effects of response r in the trajectories `table` holds
// whole: T rows x U (as above).
std::vector<double> elementary_effects(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r);

}  // namespace treedyn::designs
