// The Barnes–Hut tree against direct summation: the rms relative force error falls as the opening angle
// shrinks, on a uniform cloud and on a clumped one; the forces do not depend on the thread count. The
// vectorised, tiled direct sum against a plain double loop over the pairs.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "particle/dem/direct_gravity.hpp"
#include "particle/dem/gravity_tree.hpp"

using namespace aggkit;

namespace {

double rms_relative_error(const std::vector<Vector3>& x, const std::vector<double>& m, double theta) {
  std::vector<Vector3> direct(x.size(), {0, 0, 0}), tree(x.size(), {0, 0, 0});
  direct_gravity(x, m, 1.0, 1e-3, 1, direct);
  tree_gravity(x, m, 1.0, 1e-3, theta, 1, tree);
  double sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += dot(tree[i] - direct[i], tree[i] - direct[i]) / dot(direct[i], direct[i]);
  return std::sqrt(sum / double(x.size()));
}

std::vector<Vector3> points(bool clumped, std::size_t n) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  std::vector<Vector3> x;
  while (x.size() < n) {
    if (clumped) {  // five Gaussian clumps of different widths
      const std::size_t c = x.size() % 5;
      x.push_back({10.0 * double(c) + g(rng) * (0.5 + double(c)), g(rng) * (0.5 + double(c)), 3.0 * double(c) + g(rng)});
    } else {
      x.push_back({20 * u(rng), 20 * u(rng), 20 * u(rng)});
    }
  }
  return x;
}

}  // namespace

TEST_CASE("dem: tree gravity error falls with the opening angle", "[dem][tree]") {
  for (bool clumped : {false, true}) {
    const std::vector<Vector3> x = points(clumped, 3000);
    std::vector<double> m(x.size());
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = 0.5 + double(i % 7) * 0.25;
    double previous = 1e300;
    for (double theta : {1.0, 0.7, 0.5, 0.3, 0.2}) {
      const double error = rms_relative_error(x, m, theta);
      INFO((clumped ? "clumped" : "uniform") << " θ = " << theta << ": rms relative error " << error);
      CHECK(error < previous / 1.5);
      if (theta <= 0.5) CHECK(error < 2e-3);
      previous = error;
    }
  }
}

TEST_CASE("dem: tree forces do not depend on the thread count", "[dem][tree]") {
  const std::vector<Vector3> x = points(true, 2000);
  const std::vector<double> m(x.size(), 1.0);
  std::vector<Vector3> one(x.size(), {0, 0, 0}), four(x.size(), {0, 0, 0});
  tree_gravity(x, m, 1.0, 1e-3, 0.6, 1, one);
  tree_gravity(x, m, 1.0, 1e-3, 0.6, 4, four);
  CHECK(one == four);
}

TEST_CASE("dem: the tiled, vectorised direct sum against a plain loop, the same bits on any thread count", "[dem][gravity]") {
  std::vector<Vector3> x = points(true, 1500);
  x.push_back(x[7]);  // two coincident particles exert nothing on each other
  std::vector<double> m(x.size());
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = 0.5 + double(i % 5) * 0.3;
  const double G = 2.0, eps = 1e-2;
  std::vector<Vector3> plain(x.size(), {0, 0, 0});
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      const Vector3 d = x[j] - x[i];
      const double r2 = dot(d, d), r = std::sqrt(r2);
      const double s = r > 0 ? G * m[i] * m[j] / (r * (r2 + eps * eps)) : 0.0;
      plain[i] = plain[i] + s * d;
      plain[j] = plain[j] - s * d;
    }
  std::vector<Vector3> one(x.size(), {0, 0, 0}), three(x.size(), {0, 0, 0});
  direct_gravity(x, m, G, eps, 1, one);
  direct_gravity(x, m, G, eps, 3, three);
  CHECK(one == three);
  // Only the summation order differs: round-off of ~N ε_mach relative to the largest terms (clumps put
  // near neighbours' forces far above the total), bounded here by 1e-9 of the force scale.
  double scale = 0;
  for (const Vector3& f : plain) scale = std::max(scale, norm(f));
  Vector3 total{0, 0, 0};
  for (std::size_t i = 0; i < x.size(); ++i) {
    CHECK(norm(one[i] - plain[i]) <= 1e-9 * scale);
    total = total + one[i];
  }
  CHECK(norm(total) <= 1e-12 * scale * double(x.size()));  // momentum: pair forces cancel to round-off
}
