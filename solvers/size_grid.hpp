#pragma once
// The size classes the deterministic side solves for. The uniform grid resolves every size 1..N. The
// graded grid resolves sizes 1..K one by one and then places pivots x_{i+1} = max(x_i + 1, round(r x_i))
// up to the largest size N, so it has about K + ln(N/K)/ln r unknowns instead of N: the size range the
// oscillation regimes need at small λ (N ≥ 8/λ, the steady tail n_k ∝ k^-a e^{-ck} with c ≈ 0.65 λ;
// solvers/hopf_curve.hpp) then costs a few hundred unknowns. Each unknown N_i is the number of clusters
// represented by pivot x_i. An aggregate that forms between two pivots is shared among its neighbours so
// that its first moments are kept (the high-order moment-conserving method of classes [Alopaeus2006]): by
// default among four, x_{p-1} .. x_{p+2} around x_p < v < x_{p+1}, keeping number, mass, x² and x³
// ("four-moment"); among the nearest three, keeping number, mass and x² ("three-moment"); or between the two
// that bracket it, keeping number and mass — the fixed-pivot technique [Kumar1996] ("fixed-pivot")
// (solvers/rates_sectional.cpp). Where the pivots are the integers (the resolved block, or r close enough
// to 1 that every step rounds to +1) every aggregate lands on a pivot and every scheme is the discrete
// equation itself.
//
// Why four moments by default. Large clusters grow mostly by taking up small ones, a drift in size space.
// Two-point shares add the variance η(1-η)Δ² to every aggregate they split, a numerical diffusion that
// makes λ_crit first order in r - 1 (measured: -9.2 % at K = 64, r = 1.04 and -3.9 % at r = 1.02 for
// a = 0.75). Shares that keep x² add no spread, and λ_crit(0.75) comes to 5e-4 on the same grid
// (bench/results/log/graded-grid.md); shares that keep x³ also keep the skewness of each aggregate, and
// the change of λ_crit when r - 1 halves falls from ~1e-4 to ~1e-6 (a = 0.7 … 1, K = 64, r = 1.02;
// bench/results/RESULTS.md). The densities follow: the spacing jumps h → h + 1 of the integer pivots
// leave a dispersive ripple that three shares put at 2–4 % of n_k and four shares at ≤ 1 % (constant
// kernel, t = 20). The price of keeping more than number and mass is negative shares (a point has no
// spread, so shares that keep x² cannot all be ≥ 0), and a steady state with a steep front on a coarse
// grid may undershoot below zero; the steady-state solver refuses such roots, and the fixed-pivot scheme,
// which keeps every density ≥ 0, stays available.
//
// Densities. N_i counts the clusters of all the integer sizes whose shares go to x_i, so N_i / Δ_i is
// the density per unit size only where the shares of the sizes around x_i add up to Δ_i; near a spacing
// jump they do not (by ~10 % at the first jump 1 → 2). section_densities gives the density f_i at each
// pivot whose local exponential f_i e^{s_i (k - x_i)} over the pivot's stencil, shared by the scheme's own
// shares, gives back exactly N_i — the density the number stands for.
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "analysis/option_rows.hpp"

namespace aggkit {

// How an aggregate between two pivots is shared (see above).
enum class GridScheme { four_moment, three_moment, fixed_pivot };
const char* scheme_name(GridScheme scheme);          // "four-moment", "three-moment", "fixed-pivot"
GridScheme scheme_from_name(const std::string& name);  // throws InputError (key grid.scheme)

struct SizeGrid {
  std::size_t resolved = 0;  // K: sizes 1..K resolved one by one; 0 = the uniform grid (every size 1..N)
  double ratio = 1.0;        // r ≥ 1 of the pivots beyond K (graded grid only)
  GridScheme scheme = GridScheme::four_moment;
  bool uniform() const { return resolved == 0; }
  // Throws InputError (keys grid.resolved, grid.ratio) on a graded grid outside its option rows' ranges
  // (K ≥ 2, 1 ≤ r ≤ 4).
  void validate() const;
  // "uniform", "graded(K=64, r=1.02)" (four-moment) or "graded(K=64, r=1.02, fixed-pivot)"
  std::string describe() const;
  // The largest N a model may have on this grid: 10^8 on the uniform grid (N unknowns to store), 2^62 on a
  // graded one (ln N / ln r classes; pivots that stay ordered in double precision and within size_t).
  std::size_t largest_size() const;
  // The grid with r - 1 halved (a graded grid's refinement in r at fixed K; the uniform grid is its own).
  SizeGrid refined() const;
};

// The keys of a graded grid, `grid = { resolved = K, ratio = r, scheme = ".." }` (analysis/option_rows.hpp):
// resolved and ratio must be given, scheme defaults to SizeGrid's. A scene's [model] grid and a scan's
// hopf_grid are read through these rows, and SizeGrid::validate checks their ranges.
const OptionRows<SizeGrid>& size_grid_option_rows();

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
// with Σ w_m x_m^p = v^p for p = 0, 1 (every scheme), p = 2 (three- and four-moment) and p = 3
// (four-moment): the Lagrange weights w_m = Π_{l≠m} (v - x_l)/(x_m - x_l) of the stencil [Alopaeus2006].
// A v on a pivot lands there whole. The stencils keep to pivots at or beyond x_K: across the jump from
// unit spacing a stencil would give its far pivot a large negative share, so just above x_K they look
// forward (and near x_M backward, to stay on the grid). Four-moment: x_{p-1} .. x_{p+2} for
// x_p < v < x_{p+1}; three-moment: the nearest three. first = M: v > x_M.
struct PivotShare {
  std::size_t first = 0;
  int count = 1;
  double weight[4] = {1.0, 0.0, 0.0, 0.0};
};
PivotShare pivot_share(std::span<const double> pivots, double v, GridScheme scheme, std::size_t resolved);

// The density per unit size f_i at each pivot of a state of numbers N_i (see "Densities" above):
// f_i = N_i / Σ_k S_i(k) e^{s_i (k - x_i)} over the integer sizes k, S_i(k) the share of size k given to
// pivot i and s_i the log-slope of f between pivot i's neighbours, by fixed-point iteration from
// N_i / Δ_i (an exponential density is given back exactly); beside entries with N_i ≤ 0 (the far tail's
// sign changes) f keeps N_i / Δ_i. On integer pivots (the uniform grid) f = N. Sums over intervals longer
// than 64 sizes by 12-point Gauss–Legendre quadrature with the Euler–Maclaurin end terms
// (solvers/section_densities.cpp).
std::vector<double> section_densities(std::span<const double> pivots, std::span<const double> numbers,
                                      GridScheme scheme, std::size_t resolved);

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
