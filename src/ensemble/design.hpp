// Sampling designs: the uniform number u in (0, 1) of input dimension d of
// sample k is a pure function of (seed, k, d), so sample k is the same
// whichever rank computes it and in whatever order.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "common/enum_names.hpp"

namespace treedyn::ensemble {

enum class Design {
  monte_carlo,      // independent uniforms from a counter-based generator (Philox4x64)
  latin_hypercube,  // every dimension split into N strata, each hit exactly once
  sobol,            // Sobol points (Joe-Kuo direction numbers), Owen-scrambled by hashing
};

inline constexpr NameTable<Design, 3> kDesignNames{{{Design::monte_carlo, "monte_carlo"},
                                                    {Design::latin_hypercube, "latin_hypercube"},
                                                    {Design::sobol, "sobol"}}};
inline std::string_view name(Design d) { return name_in(kDesignNames, d); }
inline bool parse_design(std::string_view text, Design& out) { return parse_in(kDesignNames, text, out); }

class SampleDesign {
 public:
  SampleDesign(Design design, std::uint64_t seed, std::uint64_t samples, unsigned dimensions);

  // u in the open interval (0, 1).
  double uniform(std::uint64_t sample, unsigned dimension) const;
  // All dimensions of one sample at once (u.size() == dimensions()).
  void point(std::uint64_t sample, std::span<double> u) const;

  Design design() const { return design_; }
  unsigned dimensions() const { return dimensions_; }

 private:
  Design design_;
  std::uint64_t seed_;
  std::uint64_t samples_;
  unsigned dimensions_;
};

// Independent uniform in (0, 1) from Philox4x64 keyed by seed, counter
// (sample, dimension, stream).
double counter_uniform(std::uint64_t seed, std::uint64_t sample, std::uint64_t dimension,
                       std::uint64_t stream);

// A pseudorandom permutation of [0, n) keyed by (seed, stream): a Feistel
// network on the next power of two with cycle walking. Evaluated pointwise.
std::uint64_t permute_index(std::uint64_t index, std::uint64_t n, std::uint64_t seed,
                            std::uint64_t stream);

// The unscrambled Sobol sequence in Boost's (Joe-Kuo) tables, Gray-code order:
// point k, dimension d, as a 32-bit fraction numerator (point = value / 2^32).
std::uint32_t sobol_bits(std::uint64_t k, unsigned dimension, unsigned dimensions);

}  // namespace treedyn::ensemble
