// Gyration tensor, relative contacts N_c and pair distribution P(r) on sets whose values are known exactly.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "analysis/input_error.hpp"
#include "analysis/shape.hpp"
#include "tests/analysis/known_shapes.hpp"

using namespace aggkit;
using aggkit::testing::Points;

namespace {

// A point set with exactly the second moments of the uniformly filled ellipse of semi-axes a, b: rings of
// equal area in the unit disc (radii sqrt((j - 1/2)/J), j = 1..J) with M equally spaced angles each,
// stretched by (a, b), rotated by `angle` and shifted. ⟨x²⟩ on the disc = (1/J) Σ_j ρ_j² · ⟨cos²⟩ =
// (1/J²) Σ_j (j - 1/2) · 1/2 = 1/4 exactly, ⟨xy⟩ = 0 (M >= 3), so the tensor has eigenvalues a²/4, b²/4.
Points ellipse_rings(double a, double b, double angle, int rings = 40, int per_ring = 64) {
  Points p;
  for (int j = 1; j <= rings; ++j)
    for (int k = 0; k < per_ring; ++k) {
      const double rho = std::sqrt((j - 0.5) / rings), phi = 2 * std::numbers::pi * (k + 0.5) / per_ring;
      const double x = a * rho * std::cos(phi), y = b * rho * std::sin(phi);
      p.push_back({3 + x * std::cos(angle) - y * std::sin(angle), -2 + x * std::sin(angle) + y * std::cos(angle), 0});
    }
  return p;
}

ParticleConfiguration configuration(Points p, int dimension, double radius = 1.0) {
  ParticleConfiguration c;
  c.dimension = dimension;
  c.radius = radius;
  c.positions = std::move(p);
  return c;
}

}  // namespace

TEST_CASE("shape: gyration of an ellipse-shaped set has eigenvalues a²/4, b²/4 and its orientation") {
  const double a = 3, b = 1;
  for (double angle : {0.0, 0.4, 2.0}) {
    const Gyration g = gyration(ellipse_rings(a, b, angle), 2);
    // exact up to round-off (sums of ~2500 terms): relative 1e-12
    CHECK(g.eigenvalues[0] == Approx(a * a / 4).epsilon(1e-12));
    CHECK(g.eigenvalues[1] == Approx(b * b / 4).epsilon(1e-12));
    CHECK(g.eigenvalues[2] == 0.0);
    CHECK(g.aspect_ratio == Approx(a * a / (b * b)).epsilon(1e-12));
    CHECK(g.orientation == Approx(angle).margin(1e-12));
    CHECK(std::hypot(g.principal_axis[0], g.principal_axis[1]) == Approx(1).epsilon(1e-14));
    CHECK(g.radius_of_gyration == Approx(std::sqrt((a * a + b * b) / 4)).epsilon(1e-12));
  }
}

TEST_CASE("shape: gyration of random points filling an ellipse, within the sampling error") {
  // Uniform points by rejection: for the unit disc Var(x²) = ⟨x⁴⟩ - ⟨x²⟩² = 1/8 - 1/16, so the mean of
  // x² over n points has relative standard error sqrt(1/16)/(1/4)/sqrt(n) = 1/sqrt(n) = 0.32 % for
  // n = 10^5; tolerance 5 standard errors (the seed is fixed, so this is deterministic).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double a = 2, b = 0.5, angle = 2.5;
  Points p;
  while (p.size() < 100000) {
    const double x = u(rng), y = u(rng);
    if (x * x + y * y > 1) continue;
    p.push_back({a * x * std::cos(angle) - b * y * std::sin(angle), a * x * std::sin(angle) + b * y * std::cos(angle), 0});
  }
  const Gyration g = gyration(p, 2);
  CHECK(g.eigenvalues[0] == Approx(a * a / 4).epsilon(0.016));
  CHECK(g.eigenvalues[1] == Approx(b * b / 4).epsilon(0.016));
  CHECK(g.orientation == Approx(angle).margin(0.01));
}

TEST_CASE("shape: gyration in 3-D of six points on rotated axes") {
  // ±a e1, ±b e2, ±c e3: S = diag(a², b², c²)/3 in the rotated frame; the principal axis is ±R e1.
  const double a = 4, b = 2, c = 1, t = 0.7;
  const std::array<std::array<double, 3>, 3> rotation{{{std::cos(t), -std::sin(t), 0},
                                                       {std::sin(t) * std::cos(t), std::cos(t) * std::cos(t), -std::sin(t)},
                                                       {std::sin(t) * std::sin(t), std::cos(t) * std::sin(t), std::cos(t)}}};
  Points p;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      const double length = sign * std::array<double, 3>{a, b, c}[axis];
      p.push_back({rotation[0][axis] * length, rotation[1][axis] * length, rotation[2][axis] * length});
    }
  const Gyration g = gyration(p, 3);
  CHECK(g.eigenvalues[0] == Approx(a * a / 3).epsilon(1e-12));
  CHECK(g.eigenvalues[1] == Approx(b * b / 3).epsilon(1e-12));
  CHECK(g.eigenvalues[2] == Approx(c * c / 3).epsilon(1e-12));
  const double dot = g.principal_axis[0] * rotation[0][0] + g.principal_axis[1] * rotation[1][0] +
                     g.principal_axis[2] * rotation[2][0];
  CHECK(std::abs(dot) == Approx(1).epsilon(1e-12));
}

TEST_CASE("shape: N_c of a full hexagonal patch matches the count of its nearest-neighbour bonds") {
  // In a hexagon of s particles per edge (N = 3s(s-1)+1) only nearest neighbours (2R) lie within 2.1R
  // (the next shell is at 2√3 R). Interior particles have 6 neighbours, the 6 corners 3 and the 6(s-2)
  // other edge particles 4: Σ_i deg = 6N - 6·3 - 6(s-2)·2 = 6N - 12s + 6, so
  // N_c = Σ deg / (6N) = 1 - (2s - 1)/N exactly (→ 1 for an infinite hexagonal packing).
  for (int s : {2, 5, 12}) {
    const auto c = configuration(aggkit::testing::hexagonal_patch(s, 1.0, {1.5, -3, 0}), 2);
    const double n = 3.0 * s * (s - 1) + 1;
    REQUIRE(c.positions.size() == std::size_t(n));
    CHECK(relative_contacts(c) == Approx(1 - (2.0 * s - 1) / n).epsilon(1e-14));
    // Counting i = j as well adds one to every particle's neighbour count.
    CHECK(relative_contacts(c, 2.1, ContactCounting::with_self) == Approx(1 - (2.0 * s - 1) / n + 1.0 / 6).epsilon(1e-14));
  }
}

TEST_CASE("shape: N_c of a cubic lattice and of a periodic square lattice") {
  // n³ simple cubic block (3-D, N_max = 12): 3n²(n-1) bonds, N_c = 2·3n²(n-1)/(12 n³) = (n-1)/(2n).
  const auto cube = configuration(aggkit::testing::cubic_lattice(6, 6, 6, 1.0), 3);
  CHECK(relative_contacts(cube) == Approx(5.0 / 12).epsilon(1e-14));
  CHECK(relative_contacts(cube, 2.1, ContactCounting::with_self) == Approx(6.0 / 12).epsilon(1e-14));
  // 10 x 10 square lattice filling a periodic box of side 20: every particle has 4 neighbours, N_c = 4/6.
  auto square = configuration(aggkit::testing::cubic_lattice(10, 10, 1, 1.0, {0.5, 0.5, 0}), 2);
  square.periodic = true;
  square.box = {20, 20, 0};
  CHECK(relative_contacts(square) == Approx(4.0 / 6).epsilon(1e-14));
  square.periodic = false;  // walls: 2·180 bonds / (6·100)
  CHECK(relative_contacts(square) == Approx(360.0 / 600).epsilon(1e-14));
  CHECK(relative_contacts(configuration({}, 2)) == 0.0);
}

TEST_CASE("shape: pair distribution of four particles counted by hand") {
  // Pair distances: |01| = 3, |02| = 4, |12| = 5, |23| = √136 = 11.66, |13| = √149 = 12.21, |03| = √200 = 14.14.
  // P(r) = (1/N) Σ_{i≠j} 1{d_ij <= r} = 2·#{pairs <= r}/4.
  auto c = configuration({{0, 0, 0}, {3, 0, 0}, {0, 4, 0}, {10, 10, 0}}, 2, 1.0);
  const std::vector<double> r{15, 2.5, 3, 4, 5, 12, 12.3};  // any order; 3, 4, 5 exactly on a distance
  const auto p = pair_distribution(c, r);
  CHECK(p.r == r);
  CHECK(p.p == std::vector<double>{3.0, 0.0, 0.5, 1.0, 1.5, 2.0, 2.5});
  // Periodic box of side 12: the far particle's minimum images are at √8, √29, √40 (dx, dy reduced).
  c.periodic = true;
  c.box = {12, 12, 0};
  const std::vector<double> r2{2.9, 5.2, 5.5, 6.5};
  CHECK(pair_distribution(c, r2).p == std::vector<double>{0.5, 2.0, 2.5, 3.0});
  CHECK_THROWS_AS(pair_distribution(c, std::vector<double>{1, -2}), InputError);
}

TEST_CASE("shape: pair distribution agrees with an O(N^2) count on a random 3-D set") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 30);
  Points p;
  for (int i = 0; i < 600; ++i) p.push_back({u(rng), u(rng), u(rng)});
  auto c = configuration(p, 3, 0.5);
  c.periodic = true;
  c.box = {30, 30, 30};
  const auto radii = pair_distribution_radii(c.radius, 18);
  CHECK(radii.front() == Approx(2 * c.radius + 1.0 * c.radius));
  CHECK(radii.back() == Approx(20 * c.radius));
  const auto result = pair_distribution(c, radii);
  for (std::size_t k = 0; k < radii.size(); ++k) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = 0; j < p.size(); ++j)
        if (i != j && squared_norm(separation(c, p[i], p[j])) <= radii[k] * radii[k]) ++count;
    CHECK(result.p[k] == Approx(double(count) / double(p.size())).epsilon(1e-15));
  }
}
