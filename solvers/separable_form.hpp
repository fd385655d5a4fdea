#pragma once
// The separable (low-rank) form of a kernel matrix: what Kernel::separable_form gives (solvers/kernels.hpp)
// and the cross approximation builds (solvers/low_rank.hpp) for the fast right-hand side.
#include <cstddef>
#include <vector>

namespace aggkit {

// K_ij ≈ Σ_{p,q} coupling[p][q] φ_p(i) φ_q(j) for sizes 1..N, coupling symmetric.
// The aggregation gain term then needs one FFT per feature φ_p (solvers/rates_fast.cpp).
struct SeparableForm {
  std::vector<std::vector<double>> features;  // features[p][k-1] = φ_p(k)
  std::vector<std::vector<double>> coupling;  // P × P, symmetric
  bool exact = true;                          // an exact factorisation, not an approximation
  double tolerance = 0.0;                     // requested relative error (approximations only)
  double max_relative_error = 0.0;            // measured max_ij |K̃_ij - K_ij| / K_ij
  std::size_t checked_entries = 0;            // how many entries that maximum was taken over
  std::size_t rank() const { return features.size(); }
};

}  // namespace aggkit
