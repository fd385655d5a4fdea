#pragma once
// The size classes the deterministic side solves for. The uniform grid resolves every size 1..N. The
// graded grid resolves sizes 1..K one by one and then places pivots x_{i+1} = max(x_i + 1, round(r x_i))
// up to the largest size N, so it has about K + ln(N/K)/ln r unknowns instead of N: the size range the
// oscillation regimes need at small λ (N ≥ 8/λ, the steady tail n_k ∝ k^-a e^{-ck} with c ≈ 0.65 λ;
// solvers/hopf_curve.hpp) then costs a few hundred unknowns. Each unknown N_i is the number of clusters
// represented by pivot x_i. An aggregate that forms between two pivots is shared among its neighbours:
// by default among the nearest three so that number, mass and the second moment are all kept — the
// three-moment shares of the high-order moment-conserving method of classes [Alopaeus2006] — or between
// the two that bracket it, keeping number and mass — the fixed-pivot technique [Kumar1996]
// (solvers/rates_sectional.cpp). Where the pivots are the integers (the resolved block, or r close
// enough to 1 that every step rounds to +1) every aggregate lands on a pivot and either scheme is the
// discrete equation itself.
//
// Why three moments by default. Large clusters grow mostly by taking up small ones, a drift in size space.
// Two-point shares add the variance η(1-η)Δ² to every aggregate they split, a numerical diffusion that
// makes λ_crit first order in r - 1 (measured: -9.2 % at K = 64, r = 1.04 and -3.9 % at r = 1.02 for
// a = 0.75); shares that keep x² add none, and the same grid gives λ_crit(0.75) to 5e-4
// (bench/log/graded-grid.md). The price is one negative share (the far neighbour of three), so a steady
// state with a steep front on a coarse grid may undershoot below zero; the steady-state solver refuses
// such roots, and the fixed-pivot scheme, which keeps every density ≥ 0, stays available.
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace aggkit {

// How an aggregate between two pivots is shared (see above).
enum class GridScheme { three_moment, fixed_pivot };
const char* scheme_name(GridScheme scheme);          // "three-moment", "fixed-pivot"
GridScheme scheme_from_name(const std::string& name);  // throws InputError (key grid.scheme)

struct SizeGrid {
  std::size_t resolved = 0;  // K: sizes 1..K resolved one by one; 0 = the uniform grid (every size 1..N)
  double ratio = 1.0;        // r ≥ 1 of the pivots beyond K (graded grid only)
  GridScheme scheme = GridScheme::three_moment;
  bool uniform() const { return resolved == 0; }
  // Throws InputError (keys grid.resolved, grid.ratio) unless K ≥ 2 and 1 ≤ r ≤ 4 on a graded grid.
  void validate() const;
  std::string describe() const;  // "uniform", "graded(K=64, r=1.02)" or "graded(K=64, r=1.02, fixed-pivot)"
  // The largest N a model may have on this grid: 10^8 on the uniform grid (N unknowns to store), 2^62 on a
  // graded one (ln N / ln r classes; pivots that stay ordered in double precision and within size_t).
  std::size_t largest_size() const;
  // The grid with r - 1 halved (a graded grid's refinement in r at fixed K; the uniform grid is its own).
  SizeGrid refined() const;
};

// The pivots x_1 < ... < x_M = N of `grid` on sizes 1..N (x_i = i on the uniform grid).
std::vector<double> grid_pivots(const SizeGrid& grid, std::size_t N);

// The width Δ_i a pivot stands for, (x_{i+1} - x_{i-1}) / 2 with x_0 = 0 and x_{M+1} = 2 x_M - x_{M-1}:
// N_i / Δ_i is the density per unit size at x_i (1 on the integers, so the resolved block is unchanged).
std::vector<double> pivot_widths(std::span<const double> pivots);

// Where an aggregate of size v lands: index p (0-based) and the share η of it given to pivot p, the rest
// (1 - η) to p + 1, with η x_p + (1 - η) x_{p+1} = v (mass) and the shares summing to 1 (number)
// [Kumar1996]. v beyond the last pivot: p = M (it leaves the grid). v below x_1 is not a size.
std::pair<std::size_t, double> fixed_pivot_share(std::span<const double> pivots, double v);

// Where an aggregate of size v lands under `scheme`: weights w_m on the pivots first .. first + count - 1
// with Σ w_m x_m^p = v^p for p = 0, 1 (both schemes) and p = 2 (three-moment: the Lagrange weights of the
// nearest three pivots [Alopaeus2006]). A v on a pivot lands there whole; the three-moment stencil keeps
// to pivots at or beyond x_K (just above x_K it looks forward: across the jump from unit spacing a stencil
// would give its far pivot a large negative share). first = M: v > x_M.
struct PivotShare {
  std::size_t first = 0;
  int count = 1;
  double weight[3] = {1.0, 0.0, 0.0};
};
PivotShare pivot_share(std::span<const double> pivots, double v, GridScheme scheme, std::size_t resolved);

// A per-size table n_k (k = 1..len) mapped onto the pivots by the same shares (number and mass kept);
// the result has one entry per pivot. On the uniform grid: the table padded with zeros to N.
std::vector<double> to_grid(std::span<const double> pivots, std::span<const double> per_size);

// A state on pivots `from` carried to pivots `to` (a Newton start when N, K or r change): the density
// per unit size N_i/Δ_i interpolated log-linearly in x where both grids overlap, and beyond the old
// range continued by the least-squares fit ln f = a + b ln x + c x over x_M/8 < x ≤ x_M/2 (the tail's
// form, c ≤ 0; the edge near x_M is distorted by the truncation and left out).
std::vector<double> regrid(std::span<const double> from, std::span<const double> state, std::span<const double> to);

// The coarse-to-fine start's extension of a steady state `coarse` (sizes 1..Nc) to sizes 1..N: n_k for
// k ≤ Nc / 2, beyond that exp(a + b ln k + c k) with a, b, c the least-squares fit of ln n_k over
// Nc / 8 < k ≤ Nc / 2 (the form of a power law with an exponential cut-off; c clamped to ≤ 0; the edge
// region beyond Nc / 2, distorted by the truncation, is not used). Where the fitted region holds
// non-positive densities the extension is zero.
std::vector<double> extend_steady_state(std::span<const double> coarse, std::size_t N);

}  // namespace aggkit
