// Random sequential addition: every pair checked by brute force (minimum image in a periodic box), every
// particle inside its region, the reachable and unreachable volume fractions; the overlap check of a given
// configuration.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "particle/common/property_law.hpp"
#include "particle/common/random_packing.hpp"

using namespace aggkit;

namespace {

// The closest approach over all pairs, as a fraction of the contact distance (>= 1: no overlap).
double closest_relative_distance(const Box& box, const std::vector<Vector3>& x, const std::vector<double>& r) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j)
      closest = std::min(closest, norm(box.minimum_image(x[j] - x[i])) / (r[i] + r[j]));
  return closest;
}

double total_volume(int d, const std::vector<double>& r) {
  double v = 0;
  for (double x : r) v += particle_volume(d, x);
  return v;
}

std::vector<double> equal_radii(std::size_t n, double r) { return std::vector<double>(n, r); }

std::vector<double> spread_radii(std::size_t n, std::uint64_t seed) {
  PropertyLaw law;
  law.distribution = Distribution::uniform;
  law.min = 0.5;
  law.max = 1.5;
  return law.draw(n, seed);
}

}  // namespace

TEST_CASE("RSA places N particles without overlap inside cubes and spheres in open space", "[particles][packing]") {
  constexpr std::size_t n = 500;
  for (int d : {2, 3})
    for (const auto shape : {PackingRegion::Shape::cube, PackingRegion::Shape::sphere})
      for (const bool spread : {false, true}) {
        const std::vector<double> r = spread ? spread_radii(n, 7) : equal_radii(n, 1.0);
        PackingRegion region;
        region.shape = shape;
        region.centre = {1.0, -2.0, d == 3 ? 3.0 : 0.0};
        // Volume fraction 0.25 (2-D) or 0.2 (3-D) of the region.
        const double volume = total_volume(d, r) / (d == 2 ? 0.25 : 0.2);
        region.size = shape == PackingRegion::Shape::cube ? std::pow(volume, 1.0 / d)
                                                          : (d == 2 ? std::sqrt(4 * volume / std::numbers::pi)
                                                                    : std::cbrt(6 * volume / std::numbers::pi));
        CHECK(region.volume(d) == Approx(volume).epsilon(1e-12));
        const Box open{d, {0, 0, 0}, Boundary::open};
        const Packing p = random_sequential_addition(open, region, r, 42);
        INFO(d << "-D, " << (shape == PackingRegion::Shape::cube ? "cube" : "sphere") << (spread ? ", spread radii" : ""));
        REQUIRE(p.complete());
        CHECK(p.attempts >= n);
        CHECK(closest_relative_distance(open, p.positions, r) >= 1.0);
        for (std::size_t i = 0; i < n; ++i) {
          const Vector3 y = p.positions[i] - region.centre;
          if (d == 2) CHECK(p.positions[i][2] == 0.0);
          if (shape == PackingRegion::Shape::sphere) {
            CHECK(norm(y) <= region.size / 2 - r[i] + 1e-12);
          } else {
            for (int a = 0; a < d; ++a) CHECK(std::abs(y[a]) <= region.size / 2 - r[i] + 1e-12);
          }
        }
        // Reproducible from the seed, different for another seed.
        CHECK(random_sequential_addition(open, region, r, 42).positions == p.positions);
        CHECK(random_sequential_addition(open, region, r, 43).positions != p.positions);
      }
}

TEST_CASE("RSA fills periodic boxes on the minimum image and reflecting boxes inside the walls", "[particles][packing]") {
  constexpr std::size_t n = 500;
  for (int d : {2, 3})
    for (const auto boundary : {Boundary::periodic, Boundary::reflecting}) {
      const std::vector<double> r = spread_radii(n, 9);
      const double side = std::pow(total_volume(d, r) / 0.3, 1.0 / d);  // ν = 0.3
      const Box box{d, {side, side, d == 3 ? side : 0.0}, boundary};
      const Packing p = random_sequential_addition(box, PackingRegion{}, r, 5);
      INFO(d << "-D " << to_string(boundary));
      REQUIRE(p.complete());
      CHECK(closest_relative_distance(box, p.positions, r) >= 1.0);
      for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < d; ++a) {
          if (boundary == Boundary::periodic) {
            CHECK(p.positions[i][a] >= 0.0);
            CHECK(p.positions[i][a] < side);
          } else {
            CHECK(p.positions[i][a] >= r[i]);
            CHECK(p.positions[i][a] <= side - r[i]);
          }
        }
    }
  // A sphere as wide as a periodic box: particles on opposite sides meet across the boundary, and the
  // minimum image keeps them apart there too.
  const double side = 40;
  const Box box{2, {side, side, 0}, Boundary::periodic};
  PackingRegion sphere{PackingRegion::Shape::sphere, {side / 2, side / 2, 0}, side};
  const std::vector<double> r = equal_radii(300, 0.6);  // ν = 0.27 of the sphere
  const Packing p = random_sequential_addition(box, sphere, r, 3);
  REQUIRE(p.complete());
  CHECK(closest_relative_distance(box, p.positions, r) >= 1.0);
}

TEST_CASE("RSA reaches 0.3 in 2-D and gives up at 0.7", "[particles][packing]") {
  const std::vector<double> r = equal_radii(1000, 0.5);
  const auto box_at = [&](double nu) {
    const double side = std::sqrt(total_volume(2, r) / nu);
    return Box{2, {side, side, 0}, Boundary::periodic};
  };
  const Packing reached = random_sequential_addition(box_at(0.3), PackingRegion{}, r, 1);
  CHECK(reached.complete());
  CHECK(closest_relative_distance(box_at(0.3), reached.positions, r) >= 1.0);
  // Above the RSA jamming fraction 0.547 no placement completes; it stops somewhat below jamming.
  const Packing jammed = random_sequential_addition(box_at(0.7), PackingRegion{}, r, 1);
  CHECK_FALSE(jammed.complete());
  const double reached_fraction = double(jammed.placed) / 1000 * 0.7;
  CHECK(reached_fraction > 0.45);
  CHECK(reached_fraction < rsa_jamming_2d + 0.01);
  // Centres in a 0.5-wide square are never 1 apart: one particle fits, the second finds no place.
  const Packing one_fits = random_sequential_addition(Box{2, {0, 0, 0}, Boundary::open},
                                                      PackingRegion{PackingRegion::Shape::cube, {0, 0, 0}, 1.5}, r, 1);
  CHECK(one_fits.placed == 1);
}

TEST_CASE("first_overlap finds the first overlapping pair, minimum image included", "[particles][packing]") {
  const std::vector<double> r{0.5, 0.5, 0.5};
  const Box open{2, {0, 0, 0}, Boundary::open};
  CHECK_FALSE(first_overlap(open, std::vector<Vector3>{{0, 0, 0}, {1, 0, 0}, {5, 5, 0}}, r));  // touching passes
  CHECK_FALSE(first_overlap(open, std::vector<Vector3>{{0, 0, 0}, {1 - 1e-12, 0, 0}, {5, 5, 0}}, r));  // rounded
  const auto pair = first_overlap(open, std::vector<Vector3>{{0, 0, 0}, {3, 0, 0}, {0.5, 0.5, 0}}, r);
  REQUIRE(pair);
  CHECK(pair->first == 0);
  CHECK(pair->second == 2);
  const Box periodic{2, {10, 10, 0}, Boundary::periodic};
  CHECK(first_overlap(periodic, std::vector<Vector3>{{0.2, 5, 0}, {9.5, 5, 0}, {5, 5, 0}}, r));
  CHECK_FALSE(first_overlap(Box{2, {10, 10, 0}, Boundary::reflecting}, std::vector<Vector3>{{0.6, 5, 0}, {9.4, 5, 0}, {5, 5, 0}}, r));
}
