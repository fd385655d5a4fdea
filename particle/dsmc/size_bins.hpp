#pragma once
// Size classes ("bins") of the binned majorant: sizes 1, 2, 3 each alone, then every octave
// [2^o, 2^{o+1}) split in two halves, so hi/lo < 1.5 in every bin ([Michelotti2013]: the acceptance rate
// of a bin pair is bounded below by the kernel's variation across the bins).
#include <bit>
#include <cstddef>
#include <cstdint>

namespace aggkit::dsmc {

constexpr std::size_t max_bins = 128;  // enough for every 64-bit size

inline std::size_t bin_of(std::uint64_t size) {
  const int octave = std::bit_width(size) - 1;  // floor(log2 size), size >= 1
  if (octave == 0) return 0;
  return std::size_t(2 * octave - 1) + std::size_t((size >> (octave - 1)) & 1U);
}

inline std::uint64_t bin_low(std::size_t bin) {
  if (bin == 0) return 1;
  const std::size_t octave = (bin + 1) / 2, half = bin + 1 - 2 * octave;
  return (std::uint64_t(1) << octave) + half * (std::uint64_t(1) << (octave - 1));
}

inline std::uint64_t bin_high(std::size_t bin) {
  if (bin == 0) return 1;
  const std::size_t octave = (bin + 1) / 2;
  return bin_low(bin) + (std::uint64_t(1) << (octave - 1)) - 1;
}

}  // namespace aggkit::dsmc
