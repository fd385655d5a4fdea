#pragma once
// Fractal dimension of a particle aggregate, two independent estimates:
//  * box counting: the number of occupied cells of grids of side s = L/2^m, C(s) ~ s^-D [Degond2024, eq. 4.8];
//  * mass–radius: the mean number of particles N(r) within r of interior particles, N(r) ~ r^D
//    [Gonzalez2011, Sec. 3.3].
// Both fit log-log by least squares between the two plateaus, over a range chosen by a fixed rule
// (below), and report that range and the slope's standard error. Pass the points of one cluster unwrapped
// across periodic boundaries (analysis/clusters.hpp, unwrap_cluster).
#include <array>
#include <span>
#include <string>
#include <vector>

namespace aggkit {

struct FractalFit {
  double dimension = 0;                          // NaN if fewer than 3 scales qualify for the fit
  double standard_error = 0;                     // of the fitted slope (least squares, points independent)
  double fit_min = 0, fit_max = 0;               // the scales (lengths) bounding the fit range
  std::vector<double> scale, count;              // the measured curve (log-log fitted between plateaus)
  int fit_points = 0;                            // scales inside the fit range
  std::string rule;                              // the fit-range rule used: "plateaus" or "published_range"
};

// Box counting on grids of side L/2^m, m = 0, 1, ... down to a side <= R/2 (L = the given box side, or if
// 0 the side of the points' bounding square/cube grown by R on each side; the grid starts at the points'
// lower corner minus R). Counts are of occupied cells (cells holding a particle centre).
// Fit rule: the longest run of consecutive levels with 4 <= C <= N/4, i.e. at least four boxes (away
// from the large-scale plateau C -> 1) and on average at least four particles per occupied box (away from
// the small-scale plateau C = N); with a given box side also C <= half the 2^(m d) cells (away from the
// box-filling regime C = 2^(m d) of a configuration that fills its box). Ties: the finer run.
// Fallback (box side given, fewer than 3 levels left, typical of dense aggregates that fill their box):
// the fixed range 3R <= s <= L/2 of [Degond2024, Sec. 4.2.1], rule
// "published_range" — comparable with their D_f, but it mixes the fractal and box-filling regimes.
// Cost: one sort of N Morton codes, then O(N) per level.
FractalFit box_counting_dimension(std::span<const std::array<double, 3>> points, int dimension,
                                  double radius, double box_side = 0);

// Mass–radius: N(r) = mean over interior centres c of #{j : |X_j - X_c| <= r} (c itself included), at
// r_k = 2R·2^(k/2). Interior rule: centres are particles within R_max/2 of the centroid (R_max = the
// largest centroid distance), at most 256 of them evenly spread in index order; a centre contributes at r
// only if its ball of radius r lies inside the aggregate's outline, the polygon (2-D: 16 directions every
// 22.5°) or polyhedron (3-D: the 26 cube-neighbour directions) of its supporting planes moved out by R.
// Fit rule: the longest run of consecutive scales with 4R <= r <= R_max/2 (beyond two diameters; balls
// inside the aggregate's inner half) and at least 4 contributing centres. Cost: O(N) per centre.
FractalFit mass_radius_dimension(std::span<const std::array<double, 3>> points, int dimension, double radius);

}  // namespace aggkit
