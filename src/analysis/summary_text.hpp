// The pieces of text the end-of-run summary (answer_summary.cpp) and the
// designs' own lines (designs/<name>/<name>_summary.cpp) share: a number, a
// ranking ("drivers" lines), a failure region.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "analysis/failure_region.hpp"
#include "analysis/ranking.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::analysis {

inline constexpr std::size_t kRankedShown = 5;  // units on a drivers line

// `v` in printf's `format`.
std::string number(double v, const char* format = "%.6g");

// The units in ranked order ("name 0.84 [0.61, 0.97]": `measure` with its
// interval `ci`, as indices within [0, 1] when `indices`), those `hidden`
// does not hide (a list's entries, one by one: noise to a reader), ">"
// between two shown neighbours where some pair between them in the full
// order is told apart, "~" where none is yet; then how many
// `samples_word` would tell the first such pair apart.
void print_ranking(std::ostream& out, const std::vector<std::string>& names, const Ranking& ranking,
                   const std::vector<double>& measure, const std::vector<double>* ci, const char* samples_word,
                   const std::vector<bool>& hidden = {}, bool indices = true);

// The inputs the failing runs (`region.runs` of them, `what`) select on, by
// importance, and a warning for every input whose truncation bound holds
// most of them.
void print_failure_region(std::ostream& out, const EnsembleSpec& spec, const FailureRegion& region, const char* what);

}  // namespace treedyn::analysis
