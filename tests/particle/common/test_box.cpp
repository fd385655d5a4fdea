// Boxes: volume fraction ↔ side, minimum image and wrapping.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "analysis/input_error.hpp"
#include "particle/common/box.hpp"

using namespace aggkit;

TEST_CASE("box side from the volume fraction and back", "[particle_common][box]") {
  // 2-D: L = R sqrt(Nπ/ν) ([Degond2024, Table 1]); 3-D: L³ = N (4π/3) R³ / ν.
  CHECK(box_side_for_volume_fraction(2, 100, 0.2, 0.1) == Approx(0.2 * std::sqrt(100 * std::numbers::pi / 0.1)));
  CHECK(box_side_for_volume_fraction(3, 1000, 1.0, 0.25) == Approx(std::cbrt(1000 * 4.0 / 3 * std::numbers::pi / 0.25)));
  const double L = box_side_for_volume_fraction(3, 500, 0.5, 0.3);
  CHECK(volume_fraction(Box{3, {L, L, L}, Boundary::periodic}, 500, 0.5) == Approx(0.3).epsilon(1e-14));
}

TEST_CASE("minimum image and wrap along periodic axes only", "[particle_common][box]") {
  const Box periodic{2, {10, 4, 0}, Boundary::periodic};
  const Vector3 d = periodic.minimum_image({9, -3, 0});
  CHECK(d[0] == Approx(-1));
  CHECK(d[1] == Approx(1));
  const Vector3 w = periodic.wrap({-0.5, 9, 0});
  CHECK(w[0] == Approx(9.5));
  CHECK(w[1] == Approx(1));
  CHECK(periodic.wrap({-1e-18, 0, 0})[0] < 10.0);  // never exactly L
  const Box walls{2, {10, 4, 0}, Boundary::reflecting};
  CHECK(walls.minimum_image({9, -3, 0})[0] == 9);
}

TEST_CASE("bad boxes and boundary names are InputErrors", "[particle_common][box]") {
  CHECK_THROWS_AS(boundary_from_name("sticky"), InputError);
  CHECK(boundary_from_name("reflecting") == Boundary::reflecting);
  CHECK_THROWS_AS((Box{4, {1, 1, 1}, Boundary::periodic}.validate()), InputError);
  CHECK_THROWS_AS((Box{2, {1, -1, 0}, Boundary::periodic}.validate()), InputError);
}

TEST_CASE("an open boundary has no box: no sides needed, positions left as they are", "[particle_common][box][particles]") {
  CHECK(boundary_from_name("open") == Boundary::open);
  CHECK(to_string(Boundary::open) == "open");
  const Box open{3, {0, 0, 0}, Boundary::open};
  CHECK_NOTHROW(open.validate());
  CHECK(std::isinf(open.volume()));
  CHECK(open.wrap({-50, 1e6, 3}) == Vector3{-50, 1e6, 3});
  CHECK(open.minimum_image({-50, 1e6, 3}) == Vector3{-50, 1e6, 3});
  CHECK_THROWS_AS((Box{4, {0, 0, 0}, Boundary::open}.validate()), InputError);
  try {
    boundary_from_name("sticky");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("\"open\"") != std::string::npos);
  }
}
