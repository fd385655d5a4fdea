#pragma once
// Halving of a population by pairs of equal size ([Liffman1992]'s duplication run in reverse, as used by
// [Kalinov2022, Sec. 2] for growing populations): of `count` particles of one size, count/2 pairs lose one
// particle each and an odd one out is kept with probability 1/2. The expected survivors are exactly count/2
// (the size distribution stays unbiased), the removed mass differs from half the mass by at most half the
// size of each odd one out, and no particle is ever split (counts stay integers).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "particle/dsmc/random.hpp"

namespace aggkit::dsmc {

// count/2, plus one with probability 1/2 when count is odd.
inline std::uint64_t halve_count(std::uint64_t count, Random& random) {
  return count / 2 + ((count & 1) != 0 ? (random.next() >> 63) : 0);
}

// Individually stored sizes halved the same way: sorted, equal sizes paired, odd ones out by coin.
inline void halve_sizes(std::vector<std::uint64_t>& sizes, Random& random) {
  std::sort(sizes.begin(), sizes.end());
  std::size_t out = 0;
  for (std::size_t i = 0; i < sizes.size();) {
    std::size_t j = i;
    while (j < sizes.size() && sizes[j] == sizes[i]) ++j;
    const std::uint64_t kept = halve_count(j - i, random);
    for (std::uint64_t k = 0; k < kept; ++k) sizes[out++] = sizes[i];
    i = j;
  }
  sizes.resize(out);
}

}  // namespace aggkit::dsmc
