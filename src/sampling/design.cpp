#include "sampling/design.hpp"

#include <Random123/philox.h>
#include <boost/random/sobol.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace treedyn::ensemble {
namespace {

// 52 random bits into (0, 1): (m + 0.5) / 2^52, exactly representable, so
// never 0 or 1 (with 53 bits the top value would round up to 1).
double to_open_unit(std::uint64_t bits) { return (static_cast<double>(bits >> 12) + 0.5) * 0x1.0p-52; }

std::uint64_t mix(std::uint64_t x) {  // SplitMix64 finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Burley's hash-based nested uniform (Owen) scramble of a 32-bit fraction
// ("Practical Hash-based Owen Scrambling", JCGT 2020): bit-reverse, apply the
// Laine-Karras permutation, reverse back.
std::uint32_t reverse_bits(std::uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

std::uint32_t laine_karras(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(laine_karras(reverse_bits(x), seed));
}

}  // namespace

double counter_uniform(std::uint64_t seed, std::uint64_t sample, std::uint64_t dimension, std::uint64_t stream) {
  r123::Philox4x64 generator;
  const r123::Philox4x64::ctr_type counter = {{sample, dimension, stream, 0}};
  const r123::Philox4x64::key_type key = {{seed, 0x7472656564796eULL}};  // "treedyn"
  return to_open_unit(generator(counter, key)[0]);
}

std::uint64_t permute_index(std::uint64_t index, std::uint64_t n, std::uint64_t seed, std::uint64_t stream) {
  if (index >= n) throw std::out_of_range("permute_index: index outside [0, n)");
  unsigned bits = 2;
  while ((std::uint64_t{1} << bits) < n) ++bits;
  if (bits % 2) ++bits;  // balanced Feistel halves
  const unsigned half = bits / 2;
  const std::uint64_t mask = (std::uint64_t{1} << half) - 1;
  const std::uint64_t key = mix(seed ^ mix(stream + 0x51ed27ULL));
  std::uint64_t x = index;
  do {  // cycle walking: re-apply until the value falls inside [0, n)
    std::uint64_t left = x >> half, right = x & mask;
    for (std::uint64_t round = 0; round < 6; ++round) {
      const std::uint64_t f = mix(right ^ mix(key + round)) & mask;
      const std::uint64_t next = left ^ f;
      left = right;
      right = next;
    }
    x = (left << half) | right;
  } while (x >= n);
  return x;
}

// Boost's engine starts after the all-zero point: seed(j) yields point j + 1.
std::uint32_t sobol_bits(std::uint64_t k, unsigned dimension, unsigned dimensions) {
  if (k == 0) return 0;
  boost::random::sobol_engine<std::uint32_t, 32> engine(dimensions);
  engine.seed(static_cast<std::uint32_t>(k - 1));
  std::uint32_t value = 0;
  for (unsigned d = 0; d <= dimension; ++d) value = engine();
  return value;
}

SampleDesign::SampleDesign(Design design, std::uint64_t seed, std::uint64_t samples, unsigned dimensions,
                           std::vector<unsigned> unit_of_dimension, const std::optional<MorrisSpec>& morris)
    : design_(design),
      seed_(seed),
      samples_(samples),
      dimensions_(dimensions),
      unit_of_dimension_(std::move(unit_of_dimension)),
      units_(dimensions) {
  if (unit_of_dimension_.empty())
    for (unsigned d = 0; d < dimensions; ++d) unit_of_dimension_.push_back(d);
  if (unit_of_dimension_.size() != dimensions)
    throw std::invalid_argument("sample design: one Saltelli unit per input dimension");
  units_ = dimensions == 0 ? 0 : *std::max_element(unit_of_dimension_.begin(), unit_of_dimension_.end()) + 1;
  radial_ = design == Design::morris && (!morris || morris->radial);
  if (design == Design::morris && !radial_) morris_.emplace(seed, morris->levels, unit_of_dimension_, units_);
  const bool two_points = design == Design::saltelli || radial_;  // A and B from 2D Sobol' dimensions
  const unsigned sobol_dimensions = two_points ? 2 * dimensions : dimensions;
  const bool uses_sobol = design == Design::sobol || two_points;
  if (uses_sobol && sobol_dimensions > boost::random::detail::qrng_tables::sobol::max_dimension)
    throw std::invalid_argument(std::string(name(design)) + " design: at most " +
                                std::to_string(boost::random::detail::qrng_tables::sobol::max_dimension) +
                                " Sobol dimensions");
  const std::uint64_t points = design == Design::saltelli ? samples / saltelli_block(units_)
                               : radial_                  ? samples / (units_ + 1u)
                                                          : samples;
  if (uses_sobol && points > 0xffffffffULL)
    throw std::invalid_argument(std::string(name(design)) + " design: at most 2^32 - 1 Sobol points");
}

void SampleDesign::sobol_point(std::uint64_t index, unsigned total, unsigned first, std::span<double> u) const {
  boost::random::sobol_engine<std::uint32_t, 32> engine(std::max(total, 1u));
  // Point 0 is all zeros; Boost's seed(j) yields point j + 1 (32-bit points).
  if (index > 0) engine.seed(static_cast<std::uint32_t>(index - 1));
  for (unsigned d = 0; d < first + u.size(); ++d) {
    const std::uint32_t bits = index > 0 ? engine() : 0u;
    if (d < first) continue;
    const auto seed32 = static_cast<std::uint32_t>(mix(seed_ ^ mix(d + 1)));
    u[d - first] = (static_cast<double>(owen_scramble(bits, seed32)) + 0.5) * 0x1.0p-32;
  }
}

void SampleDesign::two_point(const SaltelliPlace& at, std::span<double> u) const {
  const unsigned d = dimensions_;
  sobol_point(at.base, 2 * d, at.role == SaltelliRole::b ? d : 0, u);
  if (at.role != SaltelliRole::ab) return;
  double from_b = 0.0;
  for (unsigned i = 0; i < d; ++i) {
    if (unit_of_dimension_[i] != at.unit) continue;
    sobol_point(at.base, 2 * d, d + i, std::span<double>(&from_b, 1));
    u[i] = from_b;
  }
}

void SampleDesign::point(std::uint64_t sample, std::span<double> u) const {
  if (design_ == Design::sobol) return sobol_point(sample, dimensions_, 0, u);
  if (design_ == Design::saltelli) return two_point(saltelli_place(sample, units_), u);
  if (radial_) {  // run s of trajectory t: A_t (s = 0), then A_t with unit s - 1 from B_t
    const std::uint64_t t = sample / (units_ + 1u), s = sample % (units_ + 1u);
    return two_point({t, s == 0 ? SaltelliRole::a : SaltelliRole::ab, s == 0 ? 0u : static_cast<unsigned>(s - 1)}, u);
  }
  if (design_ == Design::morris) return morris_->point(sample, u);
  for (unsigned d = 0; d < u.size(); ++d) u[d] = uniform(sample, d);
}

double SampleDesign::uniform(std::uint64_t sample, unsigned dimension) const {
  switch (design_) {
    case Design::monte_carlo:
    case Design::subset_simulation:  // level 0; later levels' points come from their chains
      return counter_uniform(seed_, sample, dimension, 0);
    case Design::latin_hypercube: {
      // Stratum pi_d(k) of N, then a uniform position inside it.
      const std::uint64_t stratum = permute_index(sample, samples_, seed_, dimension);
      const double inside = counter_uniform(seed_, sample, dimension, 1);
      const double n = static_cast<double>(samples_);
      const double u = (static_cast<double>(stratum) + inside) / n;
      // Rounding must not carry u into the next stratum (or to 1).
      const double top = (static_cast<double>(stratum) + 1.0) / n;
      return u < top ? u : std::nextafter(top, 0.0);
    }
    case Design::saltelli:
    case Design::morris: {
      std::vector<double> all(dimensions_);
      point(sample, all);
      return all[dimension];
    }
    case Design::sobol: {
      const auto seed32 = static_cast<std::uint32_t>(mix(seed_ ^ mix(dimension + 1)));
      const std::uint32_t bits = owen_scramble(sobol_bits(sample, dimension, dimensions_), seed32);
      return (static_cast<double>(bits) + 0.5) * 0x1.0p-32;
    }
  }
  return 0.5;
}

}  // namespace treedyn::ensemble
