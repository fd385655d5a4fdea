#pragma once
// The Hopf bifurcation's normal form at a steady state near λ_crit: the critical eigenvector, its adjoint and
// the first Lyapunov coefficient, which says whether the bifurcation is supercritical (l1 < 0: a stable cycle
// is born where the steady state loses stability, its radius growing as sqrt(λ_crit − λ)) or subcritical
// (l1 > 0: an unstable cycle on the stable side, a jump to a distant attractor where the steady state loses
// stability) [Kuznetsov2004, Sec. 3.5]:
//   A q = μ q,  Aᵀ p = μ̄ p,  ⟨p, q⟩ = p̄ᵀ q = 1,  ‖q‖₂ = 1,
//   c1 = ½ ⟨p, B(q̄, (2iω − A)⁻¹ B(q, q))⟩ − ⟨p, B(q, A⁻¹ B(q, q̄))⟩,   l1 = Re c1 / ω,
// with A the Jacobian on the mass shell (solvers/mass_shell.hpp), ω = Im μ and B the second derivative of
// the rates. The rates are exactly quadratic in n (the aggregation and shattering terms are both K_ij n_i
// n_j), so B(u, v) = J(n + u) v − J(n) v holds exactly and the third-derivative term of the general formula
// is zero.
//
// On the unstable side (Re μ > 0, l1 < 0) the normal form ż = μ z + c1 z|z|² predicts the cycle
//   n(t) ≈ n* + 2 Re(q z(t)),  |z|² = ρ² = −Re μ / Re c1,  frequency Im μ + Im c1 ρ²,
// the start of the shooting solver (solvers/limit_cycle.hpp) near the curve, and the amplitude law
// A² ∝ (λ_crit − λ) the computed cycles must follow.
#include <complex>
#include <limits>
#include <span>
#include <vector>

#include "solvers/model.hpp"

namespace aggkit {

struct HopfNormalForm {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::complex<double> mu{nan, nan};       // the rightmost complex eigenvalue at the steady state (Im > 0)
  std::vector<std::complex<double>> q;     // its eigenvector on the model's classes (keeping the mass)
  std::complex<double> c1{nan, nan};       // the cubic coefficient of the normal form (with ‖q‖ = 1)
  double lyapunov = nan;                   // l1 = Re c1 / ω
  double eigen_residual = nan;             // max(‖A q − μ q‖, ‖Aᵀ p − μ̄ p‖) / ‖A‖_∞

  bool supercritical() const { return lyapunov < 0.0; }
  // The predicted cycle's radius ρ (NaN where the normal form has none: Re μ and Re c1 of one sign).
  double radius() const;
  double frequency() const;  // Im μ + Im c1 ρ²
  // Half the range of M0 = Σ n over the predicted cycle: 2 ρ |Σ_k q_k|.
  double m0_half_range() const;
  // A point of the predicted cycle: n* + 2 ρ Re q (the phase where Re q points), each density shifted by
  // shifted_density. Throws std::runtime_error
  // where the normal form predicts no cycle at this steady state.
  std::vector<double> cycle_point(std::span<const double> steady) const;
};

// n + shift to first order, never negative: a decrease as n exp(shift / n). In the far tail, where n is tiny,
// an eigenvector's or a secant's share can exceed it, and a negative density there sends the quadratic rates
// off; an increase stays additive (an exponential one would put mass into the giant clusters).
double shifted_density(double n, double shift);

// The normal form at `steady`, a steady state of `model` (solvers/steady_state.hpp), from the rightmost complex
// pair of its spectrum. Throws InputError for a state of the wrong length or with non-finite entries, and
// std::runtime_error where the spectrum has no complex pair.
HopfNormalForm hopf_normal_form(const AggregationModel& model, std::span<const double> steady);

}  // namespace aggkit
