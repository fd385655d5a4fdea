#pragma once
// The steady-state equations of the truncated aggregation-shattering system with the mass constraint
// replacing one equation. Neither truncation has an exact positive
// steady state: under `drop` mass leaks past N, and under `cutoff` the largest size N collides with
// nothing (K_Nj = 0) and so absorbs whatever reaches it. What is solved is the quasi-steady state of
// the sizes that still collide, with the mass leaving them reported (leak_rate):
//   drop:    F_k = f_k (k = 1..N-1),  F_N = Σ_{k≤N} k n_k - M;  at F = 0 the largest class drains at
//            f_N = -leak/N, leak = ½ Σ_{i+j>N} (i+j) K_ij n_i n_j.
//   cutoff:  n_N is pinned to 0 (F_N = n_N), F_k = f_k (k = 1..N-2), F_{N-1} = Σ_{k<N} k n_k - M; mass
//            flows into the absorbing class at leak = N ½ Σ_{i+j=N} K_ij n_i n_j. (Keeping n_N as an
//            unknown would make the problem singular: f_1..f_{N-1} do not involve n_N and are
//            homogeneous quadratic, so a whole ray c n of roots with n_N taking up the mass appears.)
// M is the mass of the model's initial state. When the leak is negligible (N large enough) both give
// the steady state of the untruncated system restricted to sizes ≤ N.
//
// The same matrix with a shift serves linear stability: with B = diag(1, ..., 1, 0, ...) (zeros on the
// mass row and the pinned row), the pencil J_F - μ B has the eigenvalues of ∂f/∂n on the mass shell;
// the trivial mode of mass conservation becomes an infinite eigenvalue of the pencil, because an
// eigenvector of ∂f/∂n with μ ≠ 0 satisfies Σ k v_k = 0 when Σ_k k ∂f_k/∂n = 0 (exact without leak).
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "solvers/discretisation.hpp"

namespace aggkit {

class MassConstrainedSystem {
 public:
  // λ must be constant in time (a steady state of a driven system is not defined); throws InputError.
  MassConstrainedSystem(const AggregationModel& model, RatesPath path = RatesPath::fast,
                        double lowrank_tolerance = 1e-12);

  std::size_t size() const { return N_; }  // unknowns: N, or the graded grid's classes
  const std::vector<double>& sizes() const { return sizes_; }  // the classes' sizes (1..N uniform)
  const Discretisation& discretisation() const { return *grid_; }
  // Newton and shift-invert with a dense LU of J_F where the discretisation asks for it (a graded grid: a
  // few hundred to a few thousand unknowns); else the matrix-free path.
  bool dense() const { return grid_->dense_solves(); }
  // Index (0-based) of the mass row; rows after it are pinned (n_k = 0).
  std::size_t mass_row() const { return mass_row_; }
  double mass() const { return mass_; }
  double lambda() const { return lambda_; }
  // ||F(n(0))||_2 with n(0) the model's initial state: the scale of the rates, used to make residuals
  // relative (a start-independent scale: a good start must not tighten the tolerance).
  double residual_scale() const { return residual_scale_; }

  void residual(std::span<const double> n, std::span<double> F);
  // ||(d_k n_k)||_2 over the free rows, d_k = ∂f_k/∂n_k: the norm of each class's loss rate, i.e. the size of
  // the gain and loss terms whose balance F_k = 0 expresses. A residual small against it is a balance to
  // that relative precision whatever the densities are (at brownian a = 0.59, λ ~ 1e-10 the steady
  // densities are ~1e-5 and the rates ~1e-10 of those at n(0), so a residual small against
  // residual_scale() alone can leave M0 5 % off).
  double balance_scale(std::span<const double> n);
  // Mass per unit time leaving the colliding sizes: past N (drop) or into the absorbing class N (cutoff).
  double leak_rate(std::span<const double> n);
  Rates& rates() { return *rates_; }

  // Linearisation at n: call before apply()/precondition().
  void set_state(std::span<const double> n);
  // J_F (row-major size()×size()) at n: ∂f/∂n on the free rows, the sizes on the mass row, identity on
  // pinned rows.
  void dense_jacobian(std::span<const double> n, std::span<double> J);
  // out = (J_F - σ B) v, J·v through the rates' exact bilinear form (no differencing).
  void apply(std::span<const double> v, std::span<double> out, double shift = 0.0);
  // z = P_σ^{-1} r with P_σ the lower-triangular part of J_F - σ B that monomer attachment dominates:
  // the diagonal, the subdiagonal ∂f_k/∂n_{k-1} and the monomer column ∂f_k/∂n_1 (rates.hpp
  // MonomerCoupling, shared with the CVODE preconditioner), plus the full mass row (k, ...) as the last
  // row (pinned rows: identity). Forward substitution, O(N).
  void precondition(std::span<const double> r, std::span<double> z, double shift = 0.0) const;

 private:
  std::unique_ptr<Discretisation> grid_;
  std::size_t N_, mass_row_;
  bool cutoff_;
  std::vector<double> sizes_;
  double mass_ = 0.0, lambda_ = 0.0, residual_scale_ = 1.0;
  std::unique_ptr<Rates> rates_;
  std::vector<double> state_, dndt_;
  Rates::MonomerCoupling coupling_;
};

// Mass of a state, Σ k n_k, and on a grid with the classes' sizes, Σ x_k n_k.
double total_mass(std::span<const double> n);
double total_mass(std::span<const double> n, std::span<const double> sizes);

}  // namespace aggkit
