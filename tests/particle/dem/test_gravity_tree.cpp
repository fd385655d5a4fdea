// The Barnes–Hut tree against direct summation: the rms relative force error falls as the opening angle
// shrinks, on a uniform cloud and on a clumped one; the forces do not depend on the thread count.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "particle/dem/gravity_tree.hpp"

using namespace aggkit;

namespace {

double rms_relative_error(const std::vector<Vector3>& x, const std::vector<double>& m, double theta) {
  std::vector<Vector3> direct(x.size(), {0, 0, 0}), tree(x.size(), {0, 0, 0});
  direct_gravity(x, m, 1.0, 1e-3, direct);
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
