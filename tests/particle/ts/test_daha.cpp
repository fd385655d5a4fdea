// The DAHA minimisation [Degond2024, eqs. 3.20–3.24] on hand-built contacts: linked spheres end touching
// (|X_i − X_j| = 2R within the ε_c measure), nothing overlaps, and random collisions of a disc with a small
// cluster all converge below the iteration cap.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "particle/ts/daha.hpp"

using namespace aggkit;

namespace {

// |d − 2R| for which √|φ| = ε_c with φ = (2R)² − d²: |φ| ≈ 4R|d − 2R|.
double contact_tolerance(const DahaProblem& p, double eps_c) { return eps_c * eps_c / (2.0 * p.contact); }

}  // namespace

TEST_CASE("DAHA: two overlapping linked discs end touching", "[ts][daha]") {
  for (const double d0 : {0.39, 0.35, 0.3, 0.2, 0.1}) {
    DahaProblem p;
    p.free = 2;
    p.x = {{0, 0, 0}, {d0, 0.01, 0}};
    p.pairs = {{0, 1, true, {0, 0, 0}}};
    const Vector3 centre0 = 0.5 * (p.x[0] + p.x[1]);
    const DahaResult r = minimise(p, DahaParameters{});
    INFO("d0 = " << d0 << ", iterations " << r.iterations);
    CHECK(r.converged);
    CHECK(r.iterations < 300);
    CHECK(std::abs(norm(p.x[1] - p.x[0]) - 0.4) <= contact_tolerance(p, 1e-2));
    // Equal and opposite forces, equal damping: the centre does not move.
    CHECK(norm(0.5 * (p.x[0] + p.x[1]) - centre0) < 1e-12);
  }
}

TEST_CASE("DAHA: three discs, a chain and a triangle, touch along every link without overlap", "[ts][daha]") {
  for (const bool triangle : {false, true}) {
    DahaProblem p;
    p.free = 3;
    p.x = triangle ? std::vector<Vector3>{{0, 0, 0}, {0.3, 0, 0}, {0.15, 0.25, 0}}
                   : std::vector<Vector3>{{0, 0, 0}, {0.3, 0, 0}, {0.62, 0.05, 0}};
    p.pairs = {{0, 1, true, {}}, {1, 2, true, {}}, {0, 2, triangle, {}}};
    const DahaResult r = minimise(p, DahaParameters{});
    INFO("triangle " << triangle << ", iterations " << r.iterations);
    CHECK(r.converged);
    CHECK(std::abs(norm(p.x[1] - p.x[0]) - 0.4) <= 3 * contact_tolerance(p, 1e-2));
    CHECK(std::abs(norm(p.x[2] - p.x[1]) - 0.4) <= 3 * contact_tolerance(p, 1e-2));
    if (triangle) CHECK(std::abs(norm(p.x[2] - p.x[0]) - 0.4) <= 3 * contact_tolerance(p, 1e-2));
    else CHECK(norm(p.x[2] - p.x[0]) > 0.4);
    CHECK(r.max_overlap <= 3e-2);
  }
}

TEST_CASE("DAHA: a fixed partner holds and a periodic shift is honoured", "[ts][daha]") {
  DahaProblem p;
  p.free = 1;
  p.x = {{9.7, 0, 0}, {0.0, 0.05, 0}};  // b is the image at 10.0 + ... in a box of side 10
  p.pairs = {{0, 1, true, {10.0, 0, 0}}};
  const DahaResult r = minimise(p, DahaParameters{});
  CHECK(r.converged);
  CHECK(p.x[1] == Vector3{0.0, 0.05, 0});
  CHECK(std::abs(norm(p.x[1] + Vector3{10.0, 0, 0} - p.x[0]) - 0.4) <= contact_tolerance(p, 1e-2));
}

TEST_CASE("DAHA: 200 random collisions of a disc with a cluster converge", "[ts][daha]") {
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::size_t iterations = 0, failures = 0;
  double worst_contact = 0;
  for (int c = 0; c < 200; ++c) {
    std::vector<Vector3> x{{0, 0, 0}};
    const std::size_t n = 2 + std::size_t(u(g) * 8);
    while (x.size() < n) {  // a random tree of touching discs
      const std::size_t k = std::size_t(u(g) * double(x.size()));
      const double a = 2 * M_PI * u(g);
      const Vector3 y = x[k] + Vector3{0.4 * std::cos(a), 0.4 * std::sin(a), 0};
      bool ok = true;
      for (const Vector3& z : x) ok = ok && norm(z - y) >= 0.3999;
      if (ok) x.push_back(y);
    }
    const std::size_t k = std::size_t(u(g) * double(n));
    const double a = 2 * M_PI * u(g), depth = 0.4 * (0.3 + 0.7 * u(g));
    x.push_back(x[k] + Vector3{depth * std::cos(a), depth * std::sin(a), 0});
    DahaProblem p;
    p.x = x;
    p.free = x.size();
    for (std::uint32_t i = 0; i < x.size(); ++i)
      for (std::uint32_t j = i + 1; j < x.size(); ++j)
        if (norm(x[i] - x[j]) < 1.2) p.pairs.push_back({i, j, norm(x[i] - x[j]) <= 0.4005, {}});
    DahaParameters q;
    q.max_iterations = 20000;
    const DahaResult r = minimise(p, q);
    iterations += r.iterations;
    failures += r.converged ? 0 : 1;
    CHECK(r.max_overlap < 0.05);
    double nearest = 1e9;
    for (std::size_t i = 0; i + 1 < p.x.size(); ++i) nearest = std::min(nearest, norm(p.x[i] - p.x.back()));
    worst_contact = std::max(worst_contact, std::abs(nearest - 0.4));
  }
  INFO("mean iterations " << double(iterations) / 200 << ", worst contact error " << worst_contact);
  CHECK(failures == 0);
  CHECK(double(iterations) / 200 < 200);  // measured 137
  CHECK(worst_contact < 2e-3);            // measured 8.2e-4 (R = 0.2)
}
