#include "analysis/shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "analysis/input_error.hpp"
#include "analysis/neighbour_grid.hpp"

namespace aggkit {

namespace {

using Matrix3 = std::array<std::array<double, 3>, 3>;

// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations (converges quadratically;
// a few sweeps reach round-off). Columns of `vectors` are the eigenvectors.
void symmetric_eigen(Matrix3 a, std::array<double, 3>& values, Matrix3& vectors) {
  vectors = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2] + off;
    if (off <= 1e-32 * scale || off == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A J (columns p, q)
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- J^T A (rows p, q)
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = vectors[k][p], vkq = vectors[k][q];
          vectors[k][p] = c * vkp - s * vkq;
          vectors[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int k = 0; k < 3; ++k) values[k] = a[k][k];
}

void check_dimension(int dimension) {
  if (dimension != 2 && dimension != 3) throw InputError("dimension", std::to_string(dimension), "must be 2 or 3");
}

}  // namespace

Gyration gyration(std::span<const std::array<double, 3>> points, int dimension) {
  check_dimension(dimension);
  Gyration g;
  if (points.empty()) return g;
  std::array<double, 3> centre{};
  for (const auto& p : points)
    for (int a = 0; a < dimension; ++a) centre[a] += p[a];
  for (int a = 0; a < dimension; ++a) centre[a] /= double(points.size());
  Matrix3 tensor{};
  for (const auto& p : points)
    for (int a = 0; a < dimension; ++a)
      for (int b = 0; b <= a; ++b) tensor[a][b] += (p[a] - centre[a]) * (p[b] - centre[b]);
  for (int a = 0; a < dimension; ++a)
    for (int b = 0; b <= a; ++b) tensor[b][a] = tensor[a][b] /= double(points.size());

  std::array<double, 3> values{};
  Matrix3 vectors{};
  symmetric_eigen(tensor, values, vectors);
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int x, int y) { return values[x] > values[y]; });
  for (int k = 0; k < 3; ++k) g.eigenvalues[k] = std::max(0.0, values[order[k]]);  // PSD up to round-off
  for (int a = 0; a < 3; ++a) g.principal_axis[a] = vectors[a][order[0]];
  g.aspect_ratio = g.eigenvalues[1] > 0 ? g.eigenvalues[0] / g.eigenvalues[1]
                   : g.eigenvalues[0] > 0 ? std::numeric_limits<double>::infinity() : 1.0;
  g.orientation = std::atan2(g.principal_axis[1], g.principal_axis[0]);
  if (g.orientation < 0) g.orientation += std::numbers::pi;
  if (g.orientation >= std::numbers::pi) g.orientation -= std::numbers::pi;
  g.radius_of_gyration = std::sqrt(g.eigenvalues[0] + g.eigenvalues[1] + g.eigenvalues[2]);
  return g;
}

double relative_contacts(const ParticleConfiguration& config, double factor, ContactCounting counting) {
  check_configuration(config);
  if (!(factor > 0) || !std::isfinite(factor))
    throw InputError("factor", format_value(factor), "the contact range factor·R needs a positive factor");
  if (config.positions.empty()) return 0.0;
  std::size_t pairs = 0;
  for_each_contact(config, config.positions, config.radii, factor * config.radius,
                   [&](std::size_t, std::size_t, const auto&, double) { ++pairs; });
  const double n_max = config.dimension == 2 ? 6.0 : 12.0;  // kissing numbers
  const double n = double(config.positions.size());
  const double self = counting == ContactCounting::with_self ? n : 0.0;  // the N terms i = j
  return (2.0 * double(pairs) + self) / (n * n_max);  // Σ_{i≠j} counts each pair twice
}

PairDistribution pair_distribution(const ParticleConfiguration& config, std::span<const double> r) {
  check_configuration(config);
  PairDistribution result;
  result.r.assign(r.begin(), r.end());
  result.p.assign(r.size(), 0.0);
  if (r.empty() || config.positions.empty()) return result;
  for (std::size_t k = 0; k < r.size(); ++k)
    if (!(r[k] > 0) || !std::isfinite(r[k]))
      throw InputError("r[" + std::to_string(k) + "]", format_value(r[k]), "radii must be positive and finite");
  // Histogram of the pair distances over the sorted radii, then a cumulative sum: O(pairs · log K).
  std::vector<double> sorted(r.begin(), r.end());
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  std::vector<double> sorted2(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k) sorted2[k] = sorted[k] * sorted[k];
  std::vector<std::size_t> histogram(sorted.size(), 0);
  // A lookup table over d² in [0, max r²] gives a lower bound on the radius index; a short forward scan
  // finishes it (exact comparisons d² <= r², whatever the spacing of the radii).
  const std::size_t table_size = 4 * sorted.size() + 16;
  const double table_scale = double(table_size) / sorted2.back();
  std::vector<std::size_t> first_at_least(table_size + 1);
  for (std::size_t b = 0; b <= table_size; ++b)
    first_at_least[b] = std::size_t(std::lower_bound(sorted2.begin(), sorted2.end(), double(b) / table_scale) - sorted2.begin());
  NeighbourGrid grid(config.positions, config.dimension, sorted.back(), config.box, config.periodic);
  grid.for_each_pair([&](std::size_t, std::size_t, const auto&, double d2) {
    // the first radius with d² <= r²; the grid only reports d² <= max r²
    const std::size_t b = std::min(table_size, std::size_t(d2 * table_scale));
    std::size_t k = first_at_least[b == 0 ? 0 : b - 1];  // one bin of slack against rounding
    while (sorted2[k] < d2) ++k;
    ++histogram[k];
  });
  std::size_t cumulative = 0;
  std::vector<double> p_sorted(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    cumulative += histogram[k];
    p_sorted[k] = 2.0 * double(cumulative) / double(config.positions.size());
  }
  for (std::size_t k = 0; k < r.size(); ++k)
    result.p[k] = p_sorted[std::size_t(std::lower_bound(sorted.begin(), sorted.end(), r[k]) - sorted.begin())];
  return result;
}

std::vector<double> pair_distribution_radii(double radius, int count) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("radius", format_value(radius), "must be positive and finite");
  if (count < 1) throw InputError("count", std::to_string(count), "needs at least one radius");
  std::vector<double> r(static_cast<std::size_t>(count));
  for (int k = 1; k <= count; ++k) r[std::size_t(k - 1)] = radius * (2.0 + 18.0 * k / count);
  return r;
}

}  // namespace aggkit
