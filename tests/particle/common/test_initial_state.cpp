// Lattice starts and initial velocities.
#include <catch2/catch.hpp>
#include <cmath>

#include "analysis/input_error.hpp"
#include "particle/common/initial_state.hpp"

using namespace aggkit;

TEST_CASE("lattice sites fill the box without overlap", "[particle_common][initial]") {
  const Box box{2, {10, 10, 0}, Boundary::reflecting};
  const auto x = lattice_positions(box, 23, 0.5);  // 5 x 5 lattice, spacing 2
  REQUIRE(x.size() == 23);
  CHECK(x[0][0] == Approx(1));
  CHECK(x[6][0] == Approx(3));
  CHECK(x[6][1] == Approx(3));
  CHECK_THROWS_AS(lattice_positions(box, 200, 0.5), InputError);  // 15 per axis: spacing 0.67 < 2R
  const auto cube = lattice_positions(Box{3, {6, 6, 6}, Boundary::periodic}, 27, 0.5);
  CHECK(cube[26][2] == Approx(5));
}

TEST_CASE("fixed speeds have that speed, uniform components have zero momentum", "[particle_common][initial]") {
  for (int d : {2, 3}) {
    const auto v = initial_velocities(d, 1000, VelocityLaw::fixed_speed, 2.0, 3);
    Vector3 mean{0, 0, 0};
    for (const auto& u : v) {
      CHECK(norm(u) == Approx(2.0).epsilon(1e-14));
      mean = mean + 1e-3 * u;
    }
    // Uniform directions: the mean of 1000 unit-speed-2 vectors is ~2/sqrt(1000 d) per component (< 5σ).
    for (int a = 0; a < d; ++a) CHECK(std::abs(mean[a]) < 5 * 2.0 / std::sqrt(1000.0 * d));
    const auto w = initial_velocities(d, 1000, VelocityLaw::uniform_components, 1.0, 3);
    Vector3 p{0, 0, 0};
    for (const auto& u : w) p = p + u;
    CHECK(norm(p) < 1e-12);
    if (d == 2) CHECK(w[0][2] == 0.0);
  }
  CHECK(initial_velocities(2, 10, VelocityLaw::fixed_speed, 1.0, 9) == initial_velocities(2, 10, VelocityLaw::fixed_speed, 1.0, 9));
}
