// Sampling designs: their names, Saltelli's blocks, and the generators
// their points are made of (counter-based uniforms, keyed permutations,
// scrambled Sobol' points). Each design's points are its own
// (src/designs/<name>/, through sampling/run_points.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "common/enum_names.hpp"

namespace treedyn::sampling {

enum class Design {
  monte_carlo,        // independent uniforms from a counter-based generator (Philox4x64)
  latin_hypercube,    // every dimension split into N strata, each hit exactly once
  sobol,              // Sobol points (Joe-Kuo direction numbers), Owen-scrambled by hashing
  saltelli,           // Saltelli's A, B, AB_i from one scrambled Sobol sequence over 2D dimensions
  subset_simulation,  // level 0 as monte_carlo, then Markov chains towards a limit (designs/subset_simulation/)
  morris,             // Morris' trajectories of elementary effects (designs/morris/)
};

inline constexpr NameTable<Design, 6> kDesignNames{{{Design::monte_carlo, "monte_carlo"},
                                                    {Design::latin_hypercube, "latin_hypercube"},
                                                    {Design::sobol, "sobol"},
                                                    {Design::saltelli, "saltelli"},
                                                    {Design::subset_simulation, "subset_simulation"},
                                                    {Design::morris, "morris"}}};

// Saltelli's design over D inputs in U units (an input alone, or a group of
// inputs whose indices are taken together; U = D without groups) and base
// size N makes N (U + 2) runs, in blocks of U + 2 per base point j (so a
// prefix of whole blocks is itself a Saltelli design): sample k = j (U + 2) + r
// is
//   r = 0:      A_j      (dimensions 0 .. D-1 of scrambled Sobol point j of 2D),
//   r = 1:      B_j      (dimensions D .. 2D-1 of the same point),
//   r = 2 + g:  AB_g,j   (A_j with the inputs of unit g taken from B_j).
enum class SaltelliRole { a, b, ab };
struct SaltelliPlace {
  std::uint64_t base = 0;  // j
  SaltelliRole role = SaltelliRole::a;
  unsigned unit = 0;  // g, for ab
};
inline std::uint64_t saltelli_block(unsigned units) { return units + 2u; }
inline SaltelliPlace saltelli_place(std::uint64_t sample, unsigned units) {
  const std::uint64_t block = saltelli_block(units), r = sample % block;
  return {sample / block,
          r == 0   ? SaltelliRole::a
          : r == 1 ? SaltelliRole::b
                   : SaltelliRole::ab,
          r >= 2 ? static_cast<unsigned>(r - 2) : 0u};
}
inline std::string_view name(Design d) { return name_in(kDesignNames, d); }
inline bool parse_design(std::string_view text, Design& out) { return parse_in(kDesignNames, text, out); }

// Independent uniform in (0, 1) from Philox4x64 keyed by seed, counter
// (sample, dimension, stream).
double counter_uniform(std::uint64_t seed, std::uint64_t sample, std::uint64_t dimension, std::uint64_t stream);

// A pseudorandom permutation of [0, n) keyed by (seed, stream): a Feistel
// network on the next power of two with cycle walking. Evaluated pointwise.
std::uint64_t permute_index(std::uint64_t index, std::uint64_t n, std::uint64_t seed, std::uint64_t stream);

// The unscrambled Sobol sequence in Boost's (Joe-Kuo) tables, Gray-code order:
// point k, dimension d, as a 32-bit fraction numerator (point = value / 2^32).
std::uint32_t sobol_bits(std::uint64_t k, unsigned dimension, unsigned dimensions);

// Owen-scrambled (by hashing, keyed by seed and dimension) Sobol point
// `index` of `total` dimensions: dimensions first .. first + u.size() - 1
// into u; and one dimension alone (the same bits).
void scrambled_sobol_point(std::uint64_t seed, std::uint64_t index, unsigned total, unsigned first,
                           std::span<double> u);
double scrambled_sobol_uniform(std::uint64_t seed, std::uint64_t index, unsigned dimension, unsigned dimensions);

// A_j or B_j of base point `at.base` over 2D scrambled Sobol' dimensions,
// and for AB, A_j with unit `at.unit`'s inputs from B_j (saltelli, and
// morris' radial steps); u.size() == unit_of_dimension.size() == D.
void saltelli_point(std::uint64_t seed, std::span<const unsigned> unit_of_dimension, const SaltelliPlace& at,
                    std::span<double> u);

// A Sobol' design within Boost's tables (dimensions) and 32-bit points;
// else std::invalid_argument naming `design`.
void check_sobol_size(std::string_view design, unsigned sobol_dimensions, std::uint64_t points);

}  // namespace treedyn::sampling
