// The datasets every design's answers are written with: per-input (or
// per-unit) values, intervals, a ranking with what tells its neighbours
// apart, and a failure region. answers_file.cpp and the writer a design's
// answers write through (answer_group_writer.hpp) share them.
#pragma once

#include <string>
#include <vector>

#include "analysis/failure_region.hpp"
#include "analysis/ranking.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::h5 {

// One value per input (or unit), labelled by `inputs`.
void write_per_input(hid_t g, const char* name, const std::vector<double>& values, const std::string& units,
                     const std::string& what, const std::vector<std::string>& inputs);

// <sg>/<name>: the units in ranked order and what tells neighbours apart
// (analysis/ranking.hpp); `samples_word` names what `needed` counts.
void write_ranking(hid_t sg, const char* name, const analysis::Ranking& ranking, const std::string& measure,
                   const std::vector<std::string>& units, const char* samples_word);

// Rows x (low, high), the rows named in the attribute '<row_word>s'.
// `units`: the values' (an index's "1").
void write_interval_matrix(hid_t g, const char* name, const std::vector<double>& v, const std::string& what,
                           const std::vector<std::string>& rows, const char* row_word, const std::string& units = "1");

// A (low, high) pair of probabilities, described.
void write_pair(hid_t g, const char* name, double low, double high, const std::string& what);

// <parent>/failure_region: what the inputs of `which_runs` say
// (analysis/failure_region.hpp), a response's exceedance's or a subset
// simulation's.
void write_failure_region(hid_t parent, const EnsembleSpec& spec, const analysis::FailureRegion& region,
                          const std::string& which_runs);

}  // namespace treedyn::h5
