// Two- and three-particle runs with contact times, merged velocities and positions computed by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "analysis/input_error.hpp"
#include "particle/common/cell_grid.hpp"
#include "particle/ed/elastic_gas.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

using namespace aggkit;

namespace {

Box box2(double side, Boundary boundary) { return {2, {side, side, 0}, boundary}; }

void check_vector(const Vector3& got, const Vector3& want, double tol = 1e-12) {
  for (int d = 0; d < 3; ++d) CHECK(got[d] == Approx(want[d]).margin(tol));
}

}  // namespace

TEST_CASE("two particles head-on merge at rest", "[ed]") {
  const std::vector<Vector3> x{{2, 5, 0}, {6, 5, 0}}, v{{1, 0, 0}, {-1, 0, 0}};
  EventDrivenAggregation ed(box2(10, Boundary::reflecting), 0.5, x, v);
  // Gap 4 − 2R = 3 closes at speed 2: contact at t = 1.5, merged velocity (1 − 1)/2 = 0.
  REQUIRE(ed.advance(1.5 - 1e-9) == EdStop::time_reached);
  CHECK(ed.clusters() == 2);
  REQUIRE(ed.advance(10.0) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(1.5).epsilon(1e-14));
  check_vector(ed.position(0), {3.5, 5, 0});
  check_vector(ed.position(1), {4.5, 5, 0});
  check_vector(ed.velocity(0), {0, 0, 0});
  CHECK(ed.kinetic_energy() == 0.0);
}

TEST_CASE("oblique contact: merged cluster moves with the mean velocity", "[ed]") {
  const std::vector<Vector3> x{{2, 5, 0}, {5, 5.6, 0}}, v{{1, 0, 0}, {0, 0, 0}};
  EventDrivenAggregation ed(box2(20, Boundary::reflecting), 0.5, x, v);
  // (3 − t)² + 0.6² = 1 → t = 2.2; then both move with (0.5, 0).
  REQUIRE(ed.advance(100.0) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(2.2).epsilon(1e-14));
  ed.advance(3.0, 0);
  check_vector(ed.position(0), {2 + 2.2 + 0.5 * 0.8, 5, 0});
  check_vector(ed.position(1), {5 + 0.5 * 0.8, 5.6, 0});
  check_vector(ed.velocity(1), {0.5, 0, 0});
  CHECK(ed.kinetic_energy() == Approx(0.25).epsilon(1e-15));  // ½·2·0.5² (was ½)
}

TEST_CASE("three particles: the pair merges first, then the third joins", "[ed]") {
  // C (v = −2) reaches B at t = (3 − 1)/2 = 1 → BC moves with −1; A (at 3 when t = 1) meets B (at 5) after
  // the gap 1 closes at speed 2: t = 1.5; final velocity (1 − 2)/3 = −1/3.
  const std::vector<Vector3> x{{2, 5, 0}, {5, 5, 0}, {8, 5, 0}}, v{{1, 0, 0}, {0, 0, 0}, {-2, 0, 0}};
  EventDrivenAggregation ed(box2(20, Boundary::periodic), 0.5, x, v);
  REQUIRE(ed.advance(100.0, 2) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(1.0).epsilon(1e-14));
  check_vector(ed.velocity(2), {-1, 0, 0});
  REQUIRE(ed.advance(100.0, 1) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(1.5).epsilon(1e-14));
  ed.advance(2.5, 0);
  for (std::uint32_t p = 0; p < 3; ++p) check_vector(ed.velocity(p), {-1.0 / 3, 0, 0}, 1e-15);
  check_vector(ed.position(0), {3.5 - 1.0 / 3, 5, 0});
  check_vector(ed.position(1), {4.5 - 1.0 / 3, 5, 0});
  check_vector(ed.position(2), {5.5 - 1.0 / 3, 5, 0});
  CHECK(ed.kinetic_energy() == Approx(1.0 / 6).epsilon(1e-14));
  check_vector(ed.momentum(), {-1, 0, 0}, 1e-14);
}

TEST_CASE("periodic boundary: contact across the box face", "[ed][periodic]") {
  // Distance through the face 1.6, σ = 1, closing speed 2: t = 0.3; the pair rests straddling x = 0.
  const std::vector<Vector3> x{{0.8, 5, 0}, {9.2, 5, 0}}, v{{-1, 0, 0}, {1, 0, 0}};
  EventDrivenAggregation ed(box2(10, Boundary::periodic), 0.5, x, v);
  REQUIRE(ed.advance(10.0) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(0.3).epsilon(1e-14));
  const auto wrapped = ed.positions();
  check_vector(wrapped[0], {0.5, 5, 0});
  check_vector(wrapped[1], {9.5, 5, 0});
  // The cluster is contiguous: unwrapped member positions are one contact distance apart.
  CHECK(norm(ed.position(1) - ed.position(0)) == Approx(1.0).epsilon(1e-14));
}

TEST_CASE("reflecting wall reverses a particle and the wall takes 2 m v", "[ed][walls]") {
  const std::vector<Vector3> x{{8, 5, 0}, {5, 5, 0}}, v{{1, 0, 0}, {0, 0, 0}};
  EventDrivenAggregation ed(box2(10, Boundary::reflecting), 0.5, x, v);
  // A reaches x = 9.5 at t = 1.5, comes back and touches B (contact at x = 6) after 3.5 more: t = 5.
  REQUIRE(ed.advance(100.0) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(5.0).epsilon(1e-14));
  CHECK(ed.counters().wall_contacts == 1);
  check_vector(ed.wall_impulse(), {2, 0, 0});
  check_vector(ed.velocity(0), {-0.5, 0, 0});
  // Momentum plus wall impulse is conserved: (1, 0) initially.
  check_vector(ed.momentum() + ed.wall_impulse(), {1, 0, 0});
}

TEST_CASE("a cluster is reflected as a whole when one member touches the wall", "[ed][walls]") {
  // A chases B and merges with it; the pair then drifts towards the wall.
  const std::vector<Vector3> x{{3, 5, 0}, {5, 5.5, 0}}, v{{2, 0, 0}, {0, 0, 0}};
  EventDrivenAggregation ed(box2(10, Boundary::reflecting), 0.5, x, v);
  // (2 − 2t)² + 0.25 = 1 → t = 1 − sqrt(0.75)/2; merged velocity (1, 0).
  REQUIRE(ed.advance(100.0, 1) == EdStop::clusters_reached);
  const double t_merge = 1 - std::sqrt(0.75) / 2;
  CHECK(ed.time() == Approx(t_merge).epsilon(1e-14));
  // B (front member) reaches x = 9.5 after 4.5 more; the whole cluster then moves with (−1, 0).
  ed.advance(t_merge + 4.5 + 1.0, 0);
  check_vector(ed.velocity(0), {-1, 0, 0});
  check_vector(ed.position(1), {8.5, 5.5, 0});
  CHECK(ed.counters().wall_contacts == 1);
}

TEST_CASE("3-D: two spheres merge head-on", "[ed][3d]") {
  const Box box{3, {10, 10, 10}, Boundary::periodic};
  const std::vector<Vector3> x{{5, 5, 2}, {5, 5, 7}}, v{{0, 0, 1}, {0, 0, -1}};
  EventDrivenAggregation ed(box, 0.5, x, v);
  // Gap 5 − 1 closes at speed 2: t = 2, at rest, centres at z = 4 and 5.
  REQUIRE(ed.advance(10.0) == EdStop::clusters_reached);
  CHECK(ed.time() == Approx(2.0).epsilon(1e-14));
  check_vector(ed.position(0), {5, 5, 4});
  check_vector(ed.position(1), {5, 5, 5});
}

TEST_CASE("the engine, its elastic gas and cell grids refuse an open boundary", "[ed][particles]") {
  const std::vector<Vector3> x{{2, 5, 0}, {6, 5, 0}}, v{{1, 0, 0}, {-1, 0, 0}};
  const Box open{2, {10, 10, 0}, Boundary::open};
  const auto refuses = [](const auto& make) {
    try {
      make();
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.key() == "boundary");
      CHECK(std::string(e.what()).find("\"open\"") != std::string::npos);
    }
  };
  refuses([&] { EventDrivenAggregation ed(open, 0.5, x, v); });
  refuses([&] { (void)make_elastic_gas(open, 0.5, x, v); });
  refuses([&] { CellGrid grid(open, 1.0, 10); });
}
