#include "sampling/design.hpp"

#include <Random123/philox.h>
#include <boost/random/sobol.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace treedyn::sampling {
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

void check_sobol_size(std::string_view design, unsigned sobol_dimensions, std::uint64_t points) {
  if (sobol_dimensions > boost::random::detail::qrng_tables::sobol::max_dimension)
    throw std::invalid_argument(std::string(design) + " design: at most " +
                                std::to_string(boost::random::detail::qrng_tables::sobol::max_dimension) +
                                " Sobol dimensions");
  if (points > 0xffffffffULL)
    throw std::invalid_argument(std::string(design) + " design: at most 2^32 - 1 Sobol points");
}

void scrambled_sobol_point(std::uint64_t seed, std::uint64_t index, unsigned total, unsigned first,
                           std::span<double> u) {
  boost::random::sobol_engine<std::uint32_t, 32> engine(std::max(total, 1u));
  // Point 0 is all zeros; Boost's seed(j) yields point j + 1 (32-bit points).
  if (index > 0) engine.seed(static_cast<std::uint32_t>(index - 1));
  for (unsigned d = 0; d < first + u.size(); ++d) {
    const std::uint32_t bits = index > 0 ? engine() : 0u;
    if (d < first) continue;
    const auto seed32 = static_cast<std::uint32_t>(mix(seed ^ mix(d + 1)));
    u[d - first] = (static_cast<double>(owen_scramble(bits, seed32)) + 0.5) * 0x1.0p-32;
  }
}

double scrambled_sobol_uniform(std::uint64_t seed, std::uint64_t index, unsigned dimension, unsigned dimensions) {
  const auto seed32 = static_cast<std::uint32_t>(mix(seed ^ mix(dimension + 1)));
  const std::uint32_t bits = owen_scramble(sobol_bits(index, dimension, dimensions), seed32);
  return (static_cast<double>(bits) + 0.5) * 0x1.0p-32;
}

void saltelli_point(std::uint64_t seed, std::span<const unsigned> unit_of_dimension, const SaltelliPlace& at,
                    std::span<double> u) {
  const auto d = static_cast<unsigned>(u.size());
  assert(unit_of_dimension.size() == d);
  scrambled_sobol_point(seed, at.base, 2 * d, at.role == SaltelliRole::b ? d : 0, u);
  if (at.role != SaltelliRole::ab) return;
  double from_b = 0.0;
  for (unsigned i = 0; i < d; ++i) {
    if (unit_of_dimension[i] != at.unit) continue;
    scrambled_sobol_point(seed, at.base, 2 * d, d + i, std::span<double>(&from_b, 1));
    u[i] = from_b;
  }
}

}  // namespace treedyn::sampling
