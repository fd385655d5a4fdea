#pragma once
// The kernel of the simulated system tabulated for small sizes: K_ij for 1 <= i, j <= `sizes`, evaluated
// once by the kernel itself (so equal to it bit for bit), read from a 32 KiB table afterwards. Each trial of
// a DSMC method evaluates K_ij for the drawn pair; for the ballistic kernel that is two cube roots and a square
// root, and most drawn pairs of a shattering population are small (monomers are most of it), so the table
// replaces most of those evaluations by one load.
#include <cstdint>
#include <vector>

#include "particle/dsmc/interaction.hpp"

namespace aggkit::dsmc {

class KernelTable {
 public:
  static constexpr std::uint64_t sizes = 64;

  explicit KernelTable(const InteractionKernel& kernel) : kernel_(kernel), values_(sizes * sizes) {
    for (std::uint64_t i = 1; i <= sizes; ++i)
      for (std::uint64_t j = 1; j <= sizes; ++j) values_[(i - 1) * sizes + (j - 1)] = kernel(i, j);
  }
  // K_ij of the simulated system (InteractionKernel::operator(), cutoff included).
  double operator()(std::uint64_t i, std::uint64_t j) const {
    if (i <= sizes && j <= sizes) return values_[(i - 1) * sizes + (j - 1)];
    return kernel_(i, j);
  }

 private:
  InteractionKernel kernel_;
  std::vector<double> values_;
};

}  // namespace aggkit::dsmc
