// Saltelli's answers in the ensemble file: /sensitivity/<response>/ its
// Sobol' indices, their verdict and their convergence.
#pragma once

#include "analysis/answers.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// Into the response's sensitivity group `sg` (a.sobol set): first_order,
// total_order and their _ci per input (and group_* per group of a grouped
// design), the verdict on N as attributes, sobol_ranking, and
// sobol_convergence (the indices of the first 1, 2, 4, ... base points).
void write_sobol(hid_t sg, const ensemble::EnsembleSpec& spec, const ensemble::ResponseAnswer& a);

}  // namespace treedyn::designs
