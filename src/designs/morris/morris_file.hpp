// Morris' answers in the ensemble file: /sensitivity/<response>/morris_*.
#pragma once

#include "designs/morris/morris_effects.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// Into the response's sensitivity group `sg`: morris_mu_star, morris_mu,
// morris_sigma (per unit), their _ci, morris_effects and morris_ranking.
void write_morris(hid_t sg, const ensemble::EnsembleSpec& spec, const MorrisIndices& m,
                  const std::string& response_units);

}  // namespace treedyn::designs
