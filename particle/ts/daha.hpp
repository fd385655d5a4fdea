#pragma once
// The damped Arrow–Hurwicz algorithm (DAHA) of [Degond2024, eqs. 3.20–3.29]: moves a set of free spheres
// to a non-overlapping configuration that locally minimises the link potential
//   W_S = ½ Σ_{(i,j) ∈ S} |X_i − X_j|²                                   [Degond2024, eqs. 3.5, 3.30]
// under φ_ij = (R_i + R_j)² − |X_i − X_j|² ≤ 0                         [Degond2024, eq. 3.4]
// for every constrained pair, some of whose partners may be held fixed (the rest of an almost rigid cluster,
// [Degond2024, Sec. 3.3]).
//
// Sign convention (derived here; the printed scheme mixes two). With the Lagrangian
// L = W_S + Σ λ_ij φ_ij [Degond2024, eq. 3.8] and d = X_j − X_i,
//   ∇_{X_i} W_S = −d (attraction),  ∇_{X_i} φ_ij = +2d,  so −λ ∇_{X_i} φ_ij pushes i away from j.
// V is the velocity of the descent (X moves along +V, so V accumulates −∇L); one iteration r → r+1 is
//   X^{r+½} = X^r + (δ/2) V^r                                             [eq. 3.20]
//   V^{r+½} = V^r − α (∇W_S + Σ λ^r ∇φ)(X^{r+½}) − γ Σ φ λ^r ∇φ(X^{r+½})   [eq. 3.21]
//   V^{r+1} = (1 − c) V^{r+½}                                             [eq. 3.22]
//   X^{r+1} = X^{r+½} + (δ/2) V^{r+1}                                     [eq. 3.23]
//   λ^{r+1} = max(0, λ^r + β φ(X^{r+1}))                                  [eq. 3.24]
// (the parameters are the tilded ones of eq. 3.24, tildes dropped as the paper does: α, γ multiply the
// forces directly). This is a drift–kick–drift discretisation of the dissipative Arrow–Hurwicz system
// [eqs. 3.15–3.16]: its fixed points are the KKT points of eq. 3.9 (forces balance, λφ = 0), and with
// 0 ≤ c ≤ 1 the damping only removes "kinetic" energy of the descent. The γ term is the gradient of
// ½ γ λ φ², an augmented-Lagrangian penalty that vanishes at the fixed point.
//
// Start [eq. 3.26]: V = 0, λ_ij = λ0 max(0, φ_ij), warm-started by ½ on every link: ½ is the multiplier of
// a touching link at a fixed point (α(−d) + α λ 2d = 0 at φ = 0), the value the paper's multipliers stored
// per pair [Degond2024, Sec. 3.3] hold from the minimisation that made the link. Starting old links at 0
// instead lets the attraction collapse every touching link of the free spheres until λ has integrated φ
// up to ½: measured, the free spheres then moved 0.46 diameters per minimisation on average in 3-D
// (0.003 with the warm start at dt_factor 0.001), restructuring the clusters and pushing them into third
// clusters (14 % of the merges came from such pushes), so TS merged faster than ED.
// Damping and multiplier rate: constant c̃ = δ c̄ and β̃ = δ β̄ (the tilded parameters of eqs. 3.20–3.24
// built from the untilded ones). The adaptive laws of eq. 3.29 (c_i = c̄ |δV_i − φ_i^A| / φ_A,
// β = β̄ √n / φ_A) were implemented and measured first: c_i starts at c̄ > 1 for two touching discs (V = 0,
// φ_i^A = φ_A), which clamps to 1 and freezes them, and β ∝ 1/φ_A grows without bound as the overlaps
// resolve. Linearising the pair dynamics around contact gives the reason: λ integrates φ, so the
// iteration is s''' + c s'' + k_γ s' + b β s = 0 with k_γ ∝ γλ(2R)² the stiffness of the γ term, which is
// stable only for c k_γ > b β (Routh–Hurwitz) — β must stay small against γ c. With the defaults below
// (γ = 1 instead of the paper's 0.3, c̄ = 2 so that c̃ = 0.3, β̄ = 1.5 so that β̃ = 0.225) 200 random
// collisions of a disc with a 2–9 disc cluster converge in 137 iterations on average, none at the cap
// (measured over c̄ ∈ {1..4}, γ ∈ {1, 3, 6}, β̄ ∈ {1.5, 3, 6} with the warm start: the fewest iterations
// without a cap hit; with γ = 0.3 no β ≥ 0.3 converged at all; tests/particle/ts/test_daha.cpp).
// Stop [eqs. 3.27–3.28]: every free sphere's move bound (δ/2)(|V^r| + |V^{r+1}|) ≤ ε_s (|X^{r+1} − X^r|
// alone vanishes at the turning points of an oscillation, where the forces are largest — measured: it
// stopped two discs at 1.6 R apart) and the mean of √|φ| over the links ≤ ε_c. Eq. 3.28 takes √φ⁺; on a
// link the gap counts too, because a link pushed apart by a large multiplier is not a KKT point
// (λ > 0 needs φ = 0) and the printed test accepted it. Constrained pairs that are not links count
// only their overlap (the max_overlap of the result). Or max_iterations (a cap hit, counted by the caller).
//
// Lengths are in the units the parameters were tuned in: the caller scales positions so that the paper's
// R = 0.2 [Degond2024, Table 1] holds (ε_c, ε_s are then the paper's values for any radius).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/vector3.hpp"

namespace aggkit {

struct DahaParameters {
  double c_bar = 2.0;     // c̄ (paper 1.3 with an adaptive law, eq. 4.1; see above)
  double delta = 0.15;    // δ
  double alpha = 0.3;     // α: attraction and multiplier forces
  double gamma = 1.0;     // γ: the φλ∇φ term (paper 0.3; see above)
  double beta_bar = 1.5;  // β̄ (paper 3; see above)
  double eps_c = 1e-2;    // ε_c: mean √φ⁺ over the links
  double eps_s = 1e-3;    // ε_s: largest move of a sphere in one iteration
  double lambda0 = 1.0;   // λ0 of eq. 3.26 (not given by the paper; 1 in its units)
  std::size_t max_iterations = 100000;
};

// One constrained pair: spheres a (free: a < free) and b (free if b < free, else fixed). `attract`: the pair
// is a link of W_S. `shift` is added to x[b] − x[a] (a periodic image, fixed for the minimisation).
struct DahaPair {
  std::uint32_t a = 0, b = 0;
  bool attract = false;
  Vector3 shift{0, 0, 0};
};

struct DahaProblem {
  double contact = 0.4;         // R_i + R_j (equal radii), in the problem's units
  std::size_t free = 0;         // x[0..free) move, the rest are fixed partners
  std::vector<Vector3> x;       // positions
  std::vector<DahaPair> pairs;  // every constrained pair, each once
  int dimension = 2;
};

struct DahaResult {
  std::size_t iterations = 0;
  bool converged = false;     // false: the iteration cap was hit
  double mean_overlap = 0;    // mean √φ⁺ over the links at the end (eq. 3.28)
  double max_overlap = 0;     // largest √φ⁺ over the constrained pairs at the end
  double start_overlap = 0;   // largest √φ⁺ at the start
};

// Minimises in place (x[0..free) change). Deterministic.
DahaResult minimise(DahaProblem& problem, const DahaParameters& parameters);

// The link potential W_S and the largest √φ⁺ of a problem's current positions (for tests).
double link_potential(const DahaProblem& problem);
double largest_overlap(const DahaProblem& problem);

}  // namespace aggkit
