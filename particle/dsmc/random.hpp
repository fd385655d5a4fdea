#pragma once
// Random numbers for DSMC: xoshiro256** [Blackman2021], seeded through SplitMix64 [Steele2014].
// Ensemble seeds: run_seed(S, r) of particle/common/seeds.hpp; the generator of a run is then seeded from
// that value, again through SplitMix64.
#include <cstdint>

#include "particle/common/seeds.hpp"

namespace aggkit::dsmc {

using aggkit::run_seed;
using aggkit::splitmix64;

class Random {
 public:
  explicit Random(std::uint64_t seed) {
    for (auto& word : s_) word = splitmix64(seed);
  }
  std::uint64_t next() {  // xoshiro256**
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  // Uniform integer in [0, n), n >= 1, without bias [Lemire2019].
  std::uint64_t below(std::uint64_t n) {
    unsigned __int128 m = (unsigned __int128)next() * n;
    std::uint64_t low = std::uint64_t(m);
    if (low < n) {
      const std::uint64_t threshold = (0 - n) % n;
      while (low < threshold) {
        m = (unsigned __int128)next() * n;
        low = std::uint64_t(m);
      }
    }
    return std::uint64_t(m >> 64);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
};

}  // namespace aggkit::dsmc
