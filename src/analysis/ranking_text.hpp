// A ranking as the end-of-run summary prints it ("drivers" lines): the
// answers' summary (answer_summary.cpp) and each design's own
// (designs/<name>/<name>_summary.cpp) share it.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "analysis/ranking.hpp"

namespace treedyn::ensemble {

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

}  // namespace treedyn::ensemble
