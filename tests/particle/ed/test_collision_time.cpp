// Contact times of two spheres in free flight against hand-solved quadratics.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "particle/ed/collision_time.hpp"

using namespace aggkit;

TEST_CASE("head-on approach: gap over closing speed", "[ed][collision_time]") {
  // |Δx| = 4, σ = 1, closing speed 2: contact after (4 − 1)/2 = 1.5.
  CHECK(collision_time({4, 0, 0}, {-2, 0, 0}, 1.0) == Approx(1.5).epsilon(1e-15));
}

TEST_CASE("oblique approach: smallest root of the quadratic", "[ed][collision_time]") {
  // Δx = (3, 0.6), Δv = (−1, 0), σ = 1: (3 − t)² + 0.36 = 1 → t = 3 − 0.8 = 2.2.
  CHECK(collision_time({3, 0.6, 0}, {-1, 0, 0}, 1.0) == Approx(2.2).epsilon(1e-14));
  // 3-D: Δx = (0, 0, 5), Δv = (0, 0, −1), σ = 2 → t = 3.
  CHECK(collision_time({0, 0, 5}, {0, 0, -1}, 2.0) == Approx(3.0).epsilon(1e-15));
}

TEST_CASE("receding, missing and grazing pairs", "[ed][collision_time]") {
  const double never = std::numeric_limits<double>::infinity();
  CHECK(collision_time({4, 0, 0}, {2, 0, 0}, 1.0) == never);       // receding
  CHECK(collision_time({4, 1.5, 0}, {-1, 0, 0}, 1.0) == never);    // impact parameter 1.5 > σ
  CHECK(collision_time({1, 0, 0}, {0, 1, 0}, 1.0) == never);       // touching, sliding tangentially (b = 0)
}

TEST_CASE("overlap by round-off while approaching collides at once", "[ed][collision_time]") {
  CHECK(collision_time({1 - 1e-14, 0, 0}, {-1, 0, 0}, 1.0) == 0.0);
  CHECK(collision_time({1 - 1e-14, 0, 0}, {1, 0, 0}, 1.0) == std::numeric_limits<double>::infinity());
}

TEST_CASE("no cancellation for a nearly tangent fast pair", "[ed][collision_time]") {
  // Δx = (d, 0) with d = 1 + ε, Δv = (−u, 0): t = ε/u exactly; the naive (−b − sqrt(b²−ac))/a loses all
  // digits of ε when u is large, the form c/(−b + sqrt(..)) keeps them (relative error ~1e-16/ε·ε).
  const double eps = 1e-10, u = 1e6;
  CHECK(collision_time({1 + eps, 0, 0}, {-u, 0, 0}, 1.0) == Approx(eps / u).epsilon(1e-5));
}
