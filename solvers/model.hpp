#pragma once
// The truncated aggregation-shattering system of [Kalinov2022, eq. 4] in its mass-conserving form (the
// printed monomer equation lacks the factor 1/2 on the double sum, without which mass is not conserved):
//   dn_1/dt = -n_1 Σ_j K_1j n_j + λ n_1 Σ_{j≥2} j K_1j n_j + (λ/2) Σ_{i,j≥2} (i+j) K_ij n_i n_j
//   dn_k/dt = (1/2) Σ_{i+j=k} K_ij n_i n_j - (1+λ) n_k Σ_j K_kj n_j          (k ≥ 2)
// with sizes k = 1..N and an explicit truncation policy. The unknowns are the densities of the size
// classes of `grid` (solvers/size_grid.hpp): every size 1..N on the uniform grid (the default), the
// fixed-pivot sections of a graded grid otherwise.
#include <cstddef>
#include <string>
#include <vector>

#include "solvers/kernels.hpp"
#include "solvers/shattering_rate.hpp"
#include "solvers/size_grid.hpp"

namespace aggkit {

enum class Truncation {
  drop,    // aggregates larger than N leave the system; the leaked mass is tracked
  cutoff,  // K_ij = 0 when i + j > N (no aggregation or shattering of such pairs): mass conserved
};
Truncation truncation_from_name(const std::string& name);  // throws InputError
std::string to_string(Truncation t);

struct AggregationModel {
  Kernel kernel = Kernel::constant();
  ShatteringRate lambda;
  std::size_t size = 0;             // N, number of size classes
  Truncation truncation = Truncation::drop;
  std::vector<double> initial;      // n_k(0) for k = 1..N (shorter tables are padded with zeros)
  SizeGrid grid;                    // the size classes solved for (default: every size 1..N)

  std::vector<double> pivots() const { return grid_pivots(grid, size); }  // sizes of the classes
  std::size_t unknowns() const { return pivots().size(); }
  // n(0) on the classes: the initial table mapped by to_grid (on the uniform grid padded to N).
  std::vector<double> initial_state() const { return to_grid(pivots(), initial); }

  // Throws InputError for N < 2, an initial table longer than N or with negative/non-finite entries.
  void validate(double t_end) const;
};

std::vector<double> monodisperse(std::size_t N, double density = 1.0);  // n_k(0) = density δ_k1

}  // namespace aggkit
