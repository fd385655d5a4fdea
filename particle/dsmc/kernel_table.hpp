#pragma once
// The kernel of the simulated system tabulated for small sizes: K_ij for 1 <= i, j <= `sizes`, evaluated
// once by the kernel itself (so equal to it bit for bit), read from a 32 KiB table afterwards. Each trial of
// a DSMC method evaluates K_ij for the drawn pair; for the ballistic kernel that is two cube roots and a square
// root, and most drawn pairs of a shattering population are small (monomers are most of it), so the table
// replaces most of those evaluations by one load. Pairs of a monomer, dimer, trimer or tetramer with a larger
// cluster (up to `row_length`) are the next most frequent ([Kalinov2022, Sec. 5]: monomers dominate the
// shattering steady state, large clusters collide most): they are read from two further tables of 64 KiB,
// one per argument order (a user kernel need not be symmetric bit for bit).
#include <cstdint>
#include <vector>

#include "particle/dsmc/interaction.hpp"

namespace aggkit::dsmc {

class KernelTable {
 public:
  static constexpr std::uint64_t sizes = 64;
  static constexpr std::uint64_t row_sizes = 4, row_length = 2048;

  explicit KernelTable(const InteractionKernel& kernel)
      : kernel_(kernel), values_(sizes * sizes), small_first_(row_sizes * row_length), small_second_(row_sizes * row_length) {
    for (std::uint64_t i = 1; i <= sizes; ++i)
      for (std::uint64_t j = 1; j <= sizes; ++j) values_[(i - 1) * sizes + (j - 1)] = kernel(i, j);
    for (std::uint64_t i = 1; i <= row_sizes; ++i)
      for (std::uint64_t j = 1; j <= row_length; ++j) {
        small_first_[(i - 1) * row_length + (j - 1)] = kernel(i, j);
        small_second_[(i - 1) * row_length + (j - 1)] = kernel(j, i);
      }
  }
  // K_ij of the simulated system (InteractionKernel::operator(), cutoff included).
  double operator()(std::uint64_t i, std::uint64_t j) const {
    if (i <= sizes && j <= sizes) return values_[(i - 1) * sizes + (j - 1)];
    if (i <= row_sizes && j <= row_length) return small_first_[(i - 1) * row_length + (j - 1)];
    if (j <= row_sizes && i <= row_length) return small_second_[(j - 1) * row_length + (i - 1)];
    return kernel_(i, j);
  }

 private:
  InteractionKernel kernel_;
  std::vector<double> values_;
  std::vector<double> small_first_;   // K(i, j), i <= row_sizes, j <= row_length
  std::vector<double> small_second_;  // K(j, i), the same pairs in the other order
};

}  // namespace aggkit::dsmc
