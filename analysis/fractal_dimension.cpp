#include "analysis/fractal_dimension.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>

#include "analysis/input_error.hpp"
#include "analysis/least_squares.hpp"

namespace aggkit {

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

void check_arguments(std::size_t, int dimension, double radius) {
  if (dimension != 2 && dimension != 3) throw InputError("dimension", std::to_string(dimension), "must be 2 or 3");
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("radius", format_value(radius), "must be positive and finite");
}

// Least-squares line through (x_k, y_k), k in [first, last] (analysis/least_squares.hpp, gsl_fit_linear):
// slope and its standard error sqrt(Σ residual² / (n - 2) / Σ (x - x̄)²).
void fit_log_log(const std::vector<double>& x, const std::vector<double>& y, std::size_t first, std::size_t last,
                 double sign, FractalFit& fit) {
  const std::size_t n = last - first + 1;
  const LineFit line = fit_line(std::span(x).subspan(first, n), std::span(y).subspan(first, n));
  fit.dimension = sign * line.slope;
  fit.standard_error = line.slope_error;
  fit.fit_points = int(n);
}

// The longest run of consecutive true entries (the later one on ties when `prefer_last`); false if shorter
// than 3 (no error estimate possible).
bool longest_run(const std::vector<char>& valid, bool prefer_last, std::size_t& first, std::size_t& last) {
  std::size_t best_length = 0;
  for (std::size_t k = 0; k < valid.size();) {
    if (!valid[k]) { ++k; continue; }
    std::size_t end = k;
    while (end + 1 < valid.size() && valid[end + 1]) ++end;
    const std::size_t length = end - k + 1;
    if (length > best_length || (prefer_last && length == best_length)) best_length = length, first = k, last = end;
    k = end + 1;
  }
  return best_length >= 3;
}

// Bit interleaving (Morton order): spreads the low bits of x so that `stride - 1` zero bits separate them.
std::uint64_t spread_bits_2(std::uint64_t x) {
  x &= 0xffffffffULL;
  x = (x | (x << 16)) & 0x0000ffff0000ffffULL;
  x = (x | (x << 8)) & 0x00ff00ff00ff00ffULL;
  x = (x | (x << 4)) & 0x0f0f0f0f0f0f0f0fULL;
  x = (x | (x << 2)) & 0x3333333333333333ULL;
  x = (x | (x << 1)) & 0x5555555555555555ULL;
  return x;
}
std::uint64_t spread_bits_3(std::uint64_t x) {
  x &= 0x1fffffULL;
  x = (x | (x << 32)) & 0x1f00000000ffffULL;
  x = (x | (x << 16)) & 0x1f0000ff0000ffULL;
  x = (x | (x << 8)) & 0x100f00f00f00f00fULL;
  x = (x | (x << 4)) & 0x10c30c30c30c30c3ULL;
  x = (x | (x << 2)) & 0x1249249249249249ULL;
  return x;
}

// Unit vectors for the aggregate's outline: 16 in the plane (every 22.5°), or in space the 26 directions
// from a cube's centre to its face centres, edge midpoints and corners.
std::vector<std::array<double, 3>> outline_directions(int dimension) {
  std::vector<std::array<double, 3>> u;
  if (dimension == 2) {
    for (int k = 0; k < 16; ++k) u.push_back({std::cos(k * std::numbers::pi / 8), std::sin(k * std::numbers::pi / 8), 0});
    return u;
  }
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        const double norm = std::sqrt(double(x * x + y * y + z * z));
        u.push_back({x / norm, y / norm, z / norm});
      }
  return u;
}

double distance2(const std::array<double, 3>& p, const std::array<double, 3>& q, int dimension) {
  double d2 = 0;
  for (int a = 0; a < dimension; ++a) d2 += (p[a] - q[a]) * (p[a] - q[a]);
  return d2;
}

// The aggregate's outline: the polygon/polyhedron of its supporting planes in fixed directions,
// h_k = max_j u_k·X_j + R; a centre's distance to the edge is min_k (h_k - u_k·c).
struct Outline {
  std::vector<std::array<double, 3>> directions;
  std::vector<double> support;
  double radius;
  Outline(std::span<const std::array<double, 3>> points, int dimension, double r)
      : directions(outline_directions(dimension)),
        support(directions.size(), -std::numeric_limits<double>::infinity()),
        radius(r) {
    for (const auto& p : points)
      for (std::size_t k = 0; k < directions.size(); ++k)
        support[k] = std::max(support[k], directions[k][0] * p[0] + directions[k][1] * p[1] + directions[k][2] * p[2]);
  }
  double edge_distance(const std::array<double, 3>& c) const {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < directions.size(); ++k)
      d = std::min(d, support[k] + radius - (directions[k][0] * c[0] + directions[k][1] * c[1] + directions[k][2] * c[2]));
    return d;
  }
};

// The mass within r_k = 2R 2^(k/2) of the centres, summed over the centres whose ball of that radius lies
// within the outline (`contributors` of them per scale).
struct MassAround {
  std::vector<double> sum;
  std::vector<std::size_t> contributors, histogram;
  explicit MassAround(std::size_t levels) : sum(levels, 0.0), contributors(levels, 0), histogram(levels) {}
  // One centre at distance `allowed` from the edge: r_k² = 4R² 2^k, so the smallest k with r_k >= d follows
  // from the binary exponent of d²/(4R²).
  void add(std::span<const std::array<double, 3>> points, const std::array<double, 3>& centre, double allowed,
           int dimension, double radius) {
    const double unit2 = 4 * radius * radius;
    const double allowed2 = allowed * allowed;
    const std::size_t levels = sum.size();
    std::fill(histogram.begin(), histogram.end(), 0);
    for (const auto& p : points) {
      const double d2 = distance2(p, centre, dimension);
      if (d2 > allowed2) continue;
      int exponent = 0;
      const double mantissa = std::frexp(d2 / unit2, &exponent);  // d²/4R² = mantissa 2^exponent
      const int k = d2 <= unit2 ? 0 : (mantissa == 0.5 ? exponent - 1 : exponent);
      if (std::size_t(k) < levels) ++histogram[std::size_t(k)];
    }
    std::size_t cumulative = 0;
    for (std::size_t k = 0; k < levels; ++k) {
      cumulative += histogram[k];
      if (unit2 * std::ldexp(1.0, int(k)) > allowed2) break;  // r_k beyond this centre's ball
      sum[k] += double(cumulative);
      ++contributors[k];
    }
  }
};

}  // namespace

FractalFit box_counting_dimension(std::span<const std::array<double, 3>> points, int dimension, double radius,
                                  double box_side) {
  check_arguments(points.size(), dimension, radius);
  if (!(box_side >= 0) || !std::isfinite(box_side))
    throw InputError("box_side", format_value(box_side), "must be 0 (the bounding box) or a positive length");
  FractalFit fit;
  fit.dimension = fit.standard_error = not_a_number;
  if (points.size() < 2) return fit;
  const std::size_t n = points.size();

  std::array<double, 3> origin{}, top{};
  double span = 0;
  for (int a = 0; a < dimension; ++a) {
    const auto [lo, hi] = std::minmax_element(points.begin(), points.end(),
                                              [a](const auto& p, const auto& q) { return p[a] < q[a]; });
    origin[a] = (*lo)[a] - radius;
    top[a] = (*hi)[a] + radius;
    span = std::max(span, top[a] - origin[a]);
  }
  const double side = box_side > 0 ? box_side : span;
  // Levels m = 0..levels with cell side side/2^m down to <= R/2; bits per axis of the finest coordinates
  // also cover points beyond `side` (an unwrapped cluster may extend past its box).
  const int max_bits = dimension == 2 ? 31 : 21;
  int levels = std::max(1, int(std::ceil(std::log2(2.0 * side / radius))));
  const int extra = std::max(0, int(std::ceil(std::log2(span / side))));
  levels = std::min(levels, max_bits - extra);
  if (levels < 1)
    throw InputError("box_side", format_value(box_side), "is too small for the points' extent");
  const int bits = levels + extra;
  const double finest = side / std::ldexp(1.0, levels);
  const double top_coordinate = std::ldexp(1.0, bits) - 1;

  std::vector<std::uint64_t> code(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t c = 0;
    for (int a = 0; a < dimension; ++a) {
      const auto u = std::uint64_t(std::clamp(std::floor((points[i][a] - origin[a]) / finest), 0.0, top_coordinate));
      c |= (dimension == 2 ? spread_bits_2(u) : spread_bits_3(u)) << a;
    }
    code[i] = c;
  }
  std::sort(code.begin(), code.end());

  std::vector<double> log_scale, log_count;
  std::vector<char> valid;
  for (int m = 0; m <= levels; ++m) {
    const int shift = dimension * (levels - m);
    std::size_t occupied = 1;
    for (std::size_t i = 1; i < n; ++i) occupied += (code[i] >> shift) != (code[i - 1] >> shift);
    const double s = side / std::ldexp(1.0, m);
    fit.scale.push_back(s);
    fit.count.push_back(double(occupied));
    log_scale.push_back(std::log(s));
    log_count.push_back(std::log(double(occupied)));
    bool ok = occupied >= 4 && 4 * occupied <= n;
    if (box_side > 0) ok = ok && 2.0 * double(occupied) <= std::ldexp(1.0, m * dimension);
    valid.push_back(ok);
  }
  std::size_t first = 0, last = 0;
  fit.rule = "plateaus";
  if (!longest_run(valid, true, first, last)) {
    if (!(box_side > 0)) return fit;
    // [Degond2024, Sec. 4.2.1]: fit over 3R <= s <= L/2 whatever the plateaus say.
    for (std::size_t m = 0; m < valid.size(); ++m)
      valid[m] = fit.scale[m] >= 3 * radius && fit.scale[m] <= side / 2;
    if (!longest_run(valid, true, first, last)) return fit;
    fit.rule = "published_range";
  }
  fit_log_log(log_scale, log_count, first, last, -1.0, fit);
  fit.fit_max = fit.scale[first];  // coarse levels come first
  fit.fit_min = fit.scale[last];
  return fit;
}

FractalFit mass_radius_dimension(std::span<const std::array<double, 3>> points, int dimension, double radius) {
  check_arguments(points.size(), dimension, radius);
  FractalFit fit;
  fit.dimension = fit.standard_error = not_a_number;
  if (points.size() < 2) return fit;
  const std::size_t n = points.size();

  std::array<double, 3> centroid{};
  for (const auto& p : points)
    for (int a = 0; a < dimension; ++a) centroid[a] += p[a];
  for (int a = 0; a < dimension; ++a) centroid[a] /= double(n);
  double r_max = 0;
  for (const auto& p : points) r_max = std::max(r_max, std::sqrt(distance2(p, centroid, dimension)));
  const Outline outline(points, dimension, radius);

  // Scales r_k = 2R 2^(k/2), k = 0..K with r_K <= R_max.
  int scales = 0;
  while (2 * radius * std::pow(2.0, 0.5 * (scales + 1)) <= r_max) ++scales;
  const std::size_t levels = std::size_t(scales) + 1;

  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < n; ++i)
    if (std::sqrt(distance2(points[i], centroid, dimension)) <= 0.5 * r_max) candidates.push_back(i);
  constexpr std::size_t max_centres = 256;
  const std::size_t centres = std::min(max_centres, candidates.size());

  MassAround mass(levels);
  for (std::size_t c = 0; c < centres; ++c) {
    const auto& centre = points[candidates[c * candidates.size() / centres]];
    const double allowed = outline.edge_distance(centre);
    if (!(allowed < 2 * radius)) mass.add(points, centre, allowed, dimension, radius);
  }

  std::vector<double> log_scale, log_count;
  std::vector<char> valid;
  for (std::size_t k = 0; k < levels && mass.contributors[k] > 0; ++k) {
    const double r = 2 * radius * std::pow(2.0, 0.5 * double(k));
    fit.scale.push_back(r);
    fit.count.push_back(mass.sum[k] / double(mass.contributors[k]));
    log_scale.push_back(std::log(r));
    log_count.push_back(std::log(fit.count.back()));
    valid.push_back(r >= 4 * radius * (1 - 1e-12) && r <= 0.5 * r_max && mass.contributors[k] >= 4);
  }
  std::size_t first = 0, last = 0;
  if (!longest_run(valid, false, first, last)) return fit;
  fit_log_log(log_scale, log_count, first, last, 1.0, fit);
  fit.fit_min = fit.scale[first];
  fit.fit_max = fit.scale[last];
  return fit;
}

}  // namespace aggkit
