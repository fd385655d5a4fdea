#pragma once
// The far field of the sectional rates on a graded grid (solvers/rates_sectional.cpp), summed in O(M P) for a
// kernel with an exact separable form K(x, y) = Σ_pq C_pq φ_p(x) φ_q(y) (Kernel::exact_factors) instead of
// pair by pair.
//
// A pair (i, j) with x_i < h_j = x_{j+1} − x_j puts its aggregate v = x_j + x_i inside (x_j, x_{j+1}), so
// every such partner i of j shares v on the same stencil f_j .. f_j + w_j − 1, with the stencil's Lagrange
// weights (solvers/size_grid.hpp pivot_share: fixed-pivot, three- or four-moment shares), which are
// polynomials of degree < 4 in t = x_i / h_j: L_m(v) = Σ_d c_jmd t^d. Column j's far partners i < I_j (the
// pair table checks each pair's stored shares against these polynomials before counting it) contribute,
// with r_ij = s w_ij (u_i v_j + u_j v_i) and R_jd = Σ_{i<I_j} r_ij x_i^d,
//   to pivot f_j + m:   Σ_d c_jmd R_jd / h_j^d             (the aggregates)
//   to class j:         −(1 + λ) R_j0                       (its collisions)
//   to the monomers:    λ (R_j1 + x_j R_j0)                 (the shattered mass)
//   to class i:         −(1 + λ) Σ_{j: I_j > i} r_ij
// where R_jd = s Σ_p g_jp (v_j U_pd(I_j) + u_j V_pd(I_j)), g_jp = Σ_q C_pq φ_q(x_j), and U_pd(I) =
// Σ_{i<I} φ_p(x_i) x_i^d u_i (V the same of v) are prefix sums, extended once as j grows (I_j is
// nondecreasing); the partners' losses are suffix sums over the columns, bucketed by I_j. Both are plain sums
// of the pair terms, never differences of partial sums, so no cancellation enters that the pair loop does
// not have. The expansion in t ∈ [0, 1) keeps the coefficients O(1).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "solvers/kernels.hpp"

namespace aggkit {

class SectionalFarField {
 public:
  static constexpr std::size_t max_stencil = 4;   // cubic shares at most
  static constexpr std::size_t max_features = 4;  // kernel factors P

  // The pivots x (increasing) and the kernel's factors; no far pairs until set_counts. Throws
  // std::invalid_argument for more than max_features factors.
  SectionalFarField(std::span<const double> x, const Kernel::Factors& factors);

  // Column j's stencil for aggregates in (x_j, x_{j+1}): pivots first .. first + width − 1 (1 ≤ width ≤ 4).
  void set_stencil(std::size_t j, std::size_t first, std::size_t width);
  // Its share for pivot first + m of the aggregate x_j + s (0 ≤ s < h_j): the Lagrange weight L_m.
  double share(std::size_t j, std::size_t m, double s) const;
  // The far partners of each column: i < count[j] (0: none), the nonzero counts nondecreasing in j, count[j] ≤ j,
  // and column j's stencil set where count[j] > 0.
  void set_counts(std::vector<std::uint32_t> count);
  std::size_t count(std::size_t j) const { return count_[j]; }
  std::size_t pairs() const;  // Σ_j count[j]

  struct Scratch {
    std::vector<double> bucket_u, bucket_v;
  };
  // gain[k] += the far pairs' contributions to class k (k < M) and monomers += their Σ (x_i + x_j) r_ij (the
  // caller adds λ times it to the monomers, as for the near pairs).
  void accumulate(double lambda, std::span<const double> u, std::span<const double> v, double scale, double* gain,
                  double& monomers, Scratch& scratch) const;

 private:
  std::vector<double> x_, h_;
  std::size_t features_;
  std::vector<double> phi_;    // M × P: φ_p(x_i)
  std::vector<double> g_;      // M × P: Σ_q C_pq φ_q(x_j)
  std::vector<double> power_;  // M × 4: x_i^d
  std::vector<std::uint32_t> first_, width_, count_;
  std::vector<std::array<double, max_stencil * max_stencil>> poly_;  // column j: c_jmd at [m * 4 + d]
};

}  // namespace aggkit
