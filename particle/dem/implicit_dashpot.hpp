#pragma once
// The normal dashpot integrated implicitly over one velocity-Verlet step, so that a contact with
// x = γ_n dt/m* ≫ 1 (an overdamped contact at dt = t_c/50) stays stable and dissipative.
//
// A θ-method on the velocities: with v½ the half-step velocities, f the forces of the step without the
// dashpots (springs, gravity), M the masses and P_c the quadratic form of contact c's separation speed
// w_c = n_c · (v_j − v_i), the next half-step velocities v' solve
//     (M + dt Σ_c θ_c γ_c P_c) v' = M v½ + dt (f − Σ_c (1 − θ_c) γ_c P_c v½),
// so that v' = v½ + dt M^{-1} (f + the dashpot forces), contact c's dashpot force being D_c = γ_c (θ_c w_c(v')
// + (1 − θ_c) w_c(v½)) against the separation; the step applies it (in both Verlet half-kicks: v' is the
// next drift velocity).
// The weight θ_c = θ(x_c), x_c = γ_c dt/m*_c, θ(x) = 1/(1 − e^{−x}) − 1/x (from 1/2 at x → 0 to 1 at
// x → ∞) makes a pair's pure dashpot relax its relative velocity by e^{−x} per step, the exact decay; the
// scheme is the trapezoidal rule (second order) for small x, L-stable for large x, and keeps the
// quasi-static creep of an overdamped contact exact (its fixed point γ w = k δ does not depend on θ).
// Unconditionally stable for any network of contacts: θ_c ≥ 1 − θ_c, so with C = dt M^{-1/2}Γ_θ M^{-1/2} ≥
// E = dt M^{-1/2}Γ_{1−θ} M^{-1/2} the pure-dashpot step (I + C)^{-1}(I − E) has its eigenvalues in (−1, 1].
// The force is clipped at zero (no attraction): a contact whose total force k δ − D comes out negative is
// removed (its spring too: the clipped law carries no force) and the system solved again, until no new
// contact is removed (an active set that only shrinks, so at most as many solves as contacts; in practice 1–3).
// The linear system (symmetric positive definite) is solved by conjugate gradients preconditioned by each
// particle's 3×3 diagonal block, over the particles that touch a contact only, in a fixed order (the result
// does not depend on any thread count).
#include <cstdint>
#include <vector>

#include "particle/common/vector3.hpp"

namespace aggkit {

struct DashpotContact {
  static constexpr std::uint32_t wall = UINT32_MAX;
  std::uint32_t i, j;    // the force is +F n on j and −F n on i; i = wall: a wall (infinite mass) pushing j
  Vector3 normal;        // unit, from i to j (from the wall into j)
  double damping;        // γ_c (times the onset weight of the contact's first step)
  double spring;         // k δ (δ clamped), ≥ 0: the force's spring part, already in f
  double reduced_mass;   // m*_c (the particle's mass for a wall)
};

// θ(x) above, from its series 1/2 + x/12 − x³/720 below x = 10^-3 (next term x⁵/30240).
double dashpot_theta(double x);

struct DashpotSolve {
  std::uint64_t solves = 0, iterations = 0;  // linear solves (active-set passes) and CG iterations
};

// The total normal force of each contact, max(0, k δ − γ w(v̂)), or 0 for a contact removed by the
// clipping; `masses`, `velocities` (v½) and `forces` (f, springs included) per particle.
// Throws std::runtime_error if conjugate gradients do not converge (relative residual 10^-12) in 10^4 iterations.
std::vector<double> implicit_dashpot_forces(const std::vector<DashpotContact>& contacts, const std::vector<double>& masses,
                                            const std::vector<Vector3>& velocities, const std::vector<Vector3>& forces, double dt,
                                            DashpotSolve& stats);

}  // namespace aggkit
