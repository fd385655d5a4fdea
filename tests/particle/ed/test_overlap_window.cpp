// First overlap windows of boxes in relative uniform motion (overlap_window.hpp) against a direct scan of
// the overlap condition |y_a(t) − k L| <= s_a on a fine time grid, with and without periodic axes.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "particle/ed/overlap_window.hpp"

using namespace aggkit;

namespace {

bool overlapping(int dimension, const Vector3& y0, const Vector3& w, const Vector3& s, const Vector3& period, double t) {
  for (int a = 0; a < dimension; ++a) {
    double y = y0[a] + w[a] * t;
    if (period[a] > 0) y -= period[a] * std::nearbyint(y / period[a]);
    if (std::abs(y) > s[a]) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("overlap windows: hand cases", "[ed][overlap_window]") {
  // Non-periodic, approaching along x: |3 − 2t| <= 1 for t in [1, 2].
  const Vector3 zero{0, 0, 0};
  auto w = first_overlap(2, {3, 0.5, 0}, {-2, 0, 0}, {1, 1, 0}, zero, 1e-12);
  REQUIRE(w.kind == OverlapWindow::overlap);
  CHECK(w.begin == Approx(1.0));
  CHECK(w.end == Approx(2.0));
  // Offset along y beyond s and no y motion: never.
  CHECK(first_overlap(2, {3, 1.5, 0}, {-2, 0, 0}, {1, 1, 0}, zero, 1e-12).kind == OverlapWindow::none);
  // Periodic: moving away along x still meets the next image, L = 10: |−3 − 2t + 10| <= 1 → t in [3, 4].
  w = first_overlap(2, {-3, 0, 0}, {-2, 0, 0}, {1, 1, 0}, {10, 10, 0}, 1e-12);
  REQUIRE(w.kind == OverlapWindow::overlap);
  CHECK(w.begin == Approx(3.0));
  CHECK(w.end == Approx(4.0));
}

TEST_CASE("overlap windows agree with a direct scan", "[ed][overlap_window]") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const int dimension = trial % 2 ? 3 : 2;
    const bool periodic = trial % 3 != 0;
    const double L = 10;
    Vector3 y0{0, 0, 0}, w{0, 0, 0}, s{0, 0, 0}, period{0, 0, 0};
    for (int a = 0; a < dimension; ++a) {
      y0[a] = 8 * u(rng);
      w[a] = u(rng);
      s[a] = 1 + 0.8 * u(rng);
      if (periodic) period[a] = L;
    }
    const OverlapWindow window = first_overlap(dimension, y0, w, s, period, 1e-12);
    // First overlapping time on a grid of step 1e-3 up to t = 60.
    const double dt = 1e-3;
    double first = -1;
    for (double t = 0; t <= 60; t += dt)
      if (overlapping(dimension, y0, w, s, period, t)) {
        first = t;
        break;
      }
    INFO("trial " << trial);
    if (window.kind == OverlapWindow::recheck) {
      CHECK((first < 0 || first >= window.begin - dt));  // nothing before the recheck time
      continue;
    }
    if (first < 0) {
      CHECK((window.kind == OverlapWindow::none || window.begin > 60 - dt));
      continue;
    }
    REQUIRE(window.kind == OverlapWindow::overlap);
    CHECK(window.begin == Approx(first).margin(2 * dt));
    CHECK(overlapping(dimension, y0, w, s, period, 0.5 * (window.begin + std::min(window.end, window.begin + 1))));
  }
}

TEST_CASE("overlap windows: a bounded search returns the same window or a recheck no later than it", "[ed][overlap_window]") {
  // The engine bounds the search by steps (pair predictions) or by a horizon (contact casts); either way a
  // recheck must be a lower bound of the unbounded answer, or a contact could be skipped.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int rechecks = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int dimension = trial % 2 ? 3 : 2;
    Vector3 y0{0, 0, 0}, w{0, 0, 0}, s{0, 0, 0}, period{0, 0, 0};
    for (int a = 0; a < dimension; ++a) {
      y0[a] = 40 * u(rng);
      w[a] = u(rng);
      s[a] = 0.5 + 0.4 * u(rng);  // small boxes in a period of 100: windows rarely coincide
      period[a] = 100;
    }
    const OverlapWindow full = first_overlap(dimension, y0, w, s, period, 1e-12);
    const double horizon = 50 * (1 + u(rng));
    for (const OverlapWindow bounded : {first_overlap(dimension, y0, w, s, period, 1e-12, 3),
                                        first_overlap(dimension, y0, w, s, period, 1e-12, 64, horizon)}) {
      INFO("trial " << trial);
      if (bounded.kind == OverlapWindow::recheck) {
        ++rechecks;
        if (full.kind != OverlapWindow::none) CHECK(bounded.begin <= full.begin);
        continue;
      }
      CHECK(bounded.kind == full.kind);
      if (full.kind == OverlapWindow::overlap) {
        CHECK(bounded.begin == full.begin);
        CHECK(bounded.end == full.end);
      }
    }
  }
  CHECK(rechecks > 100);  // the bounds did cut searches short
}
