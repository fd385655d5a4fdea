// Contacts, clusters and unwrapping of spheres of their own radii R_i against a brute-force computation over
// every pair: a pair is in contact within (contact_distance / 2R̄)(R_i + R_j) (contact_distance the range of
// two spheres of the reference radius R̄), and one radius for every particle is the special case.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "analysis/clusters.hpp"
#include "analysis/shape.hpp"

using namespace aggkit;

namespace {

// N spheres of radii uniform in [0.2, 1.0] at random places of a box of side L (overlaps allowed: a dense,
// well-connected mixture).
ParticleConfiguration mixture(std::size_t n, int dimension, bool periodic, double side, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> place(0.0, side), size(0.2, 1.0);
  ParticleConfiguration c;
  c.dimension = dimension, c.periodic = periodic, c.box = {side, side, side};
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    c.positions.push_back({place(random), place(random), dimension == 3 ? place(random) : 0.0});
    c.radii.push_back(size(random));
    sum += c.radii.back();
  }
  c.radius = sum / double(n);
  return c;
}

bool touching(const ParticleConfiguration& c, std::size_t i, std::size_t j, double contact_distance) {
  const auto d = separation(c, c.positions[i], c.positions[j]);
  const double reach = contact_distance / (2 * c.radius) * (c.radius_of(i) + c.radius_of(j));
  return squared_norm(d) <= reach * reach;
}

// Cluster labels by brute force: all pairs, then the connected components by repeated relabelling.
std::vector<std::uint32_t> brute_force_clusters(const ParticleConfiguration& c, double contact_distance) {
  const std::size_t n = c.positions.size();
  std::vector<std::size_t> component(n);
  for (std::size_t i = 0; i < n; ++i) component[i] = i;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if (touching(c, i, j, contact_distance) && component[i] != component[j]) {
          const std::size_t low = std::min(component[i], component[j]);
          component[i] = component[j] = low;
          changed = true;
        }
  }
  std::vector<std::uint32_t> label_of(n, std::uint32_t(-1)), labels(n);
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (label_of[component[i]] == std::uint32_t(-1)) label_of[component[i]] = next++;
    labels[i] = label_of[component[i]];
  }
  return labels;
}

}  // namespace

TEST_CASE("polydisperse: contact clusters and relative contacts match every pair checked by brute force") {
  for (int dimension : {2, 3})
    for (bool periodic : {false, true})
      for (unsigned seed : {1u, 2u, 3u}) {
        INFO("dimension " << dimension << ", periodic " << periodic << ", seed " << seed);
        const double side = dimension == 2 ? 14.0 : 7.0;
        const ParticleConfiguration c = mixture(300, dimension, periodic, side, seed);
        const double contact_distance = 2.1 * c.radius;
        CHECK(contact_clusters(c, contact_distance) == brute_force_clusters(c, contact_distance));
        std::size_t pairs = 0;
        for (std::size_t i = 0; i < c.positions.size(); ++i)
          for (std::size_t j = i + 1; j < c.positions.size(); ++j) pairs += touching(c, i, j, contact_distance);
        const double n_max = dimension == 2 ? 6.0 : 12.0;
        // The same integer count divided the same way: equal to the last bit.
        CHECK(relative_contacts(c, 2.1) == 2.0 * double(pairs) / (300.0 * n_max));
        // The mean radius alone would count other pairs (the bug of handing the analysis one radius).
        ParticleConfiguration mean = c;
        mean.radii.clear();
        CHECK(relative_contacts(mean, 2.1) != relative_contacts(c, 2.1));
      }
}

TEST_CASE("polydisperse: one radius for every particle, given per particle, is the equal-radius case") {
  ParticleConfiguration equal = mixture(400, 3, true, 8.0, 7);
  equal.radii.assign(equal.positions.size(), 0.5);
  equal.radius = 0.5;
  ParticleConfiguration one = equal;
  one.radii.clear();
  CHECK(contact_clusters(equal, 1.05) == contact_clusters(one, 1.05));
  CHECK(relative_contacts(equal, 2.1) == relative_contacts(one, 2.1));
}

TEST_CASE("polydisperse: a chain of unequal spheres across a periodic wall is unwrapped through its contacts") {
  // Radii 1, 0.25, 1, 0.25, ... touching in a line along x that crosses x = L: centres 1.25 apart.
  ParticleConfiguration c;
  c.dimension = 3, c.periodic = true, c.box = {10, 10, 10};
  double x = 7.0, sum = 0;
  for (int k = 0; k < 6; ++k) {
    const double r = k % 2 == 0 ? 1.0 : 0.25;
    if (k > 0) x += c.radii.back() + r;
    c.positions.push_back({std::fmod(x, 10.0), 5.0, 5.0});
    c.radii.push_back(r);
    sum += r;
  }
  c.radius = sum / 6;
  const double contact_distance = 2 * c.radius * (1 + 1e-9);
  const std::vector<std::size_t> members{0, 1, 2, 3, 4, 5};
  const auto unwrapped = unwrap_cluster(c, members, contact_distance);
  for (int k = 1; k < 6; ++k) CHECK(unwrapped[k][0] - unwrapped[k - 1][0] == Approx(c.radii[k - 1] + c.radii[k]));
  // With the mean radius 0.625 every pair reaches only 1.25: still connected here, but a pair of the large
  // spheres alone (2.0 apart) is not: the true radii join it.
  ParticleConfiguration pair;
  pair.dimension = 3, pair.periodic = true, pair.box = {10, 10, 10};
  pair.positions = {{9.5, 5, 5}, {1.5, 5, 5}};
  pair.radii = {1.0, 1.0};
  pair.radius = 0.625;  // the reference radius of the contact range, as for a mixture's mean
  CHECK(contact_clusters(pair, 2 * 0.625 * (1 + 1e-9)) == std::vector<std::uint32_t>{0, 0});
  pair.radii.clear();
  CHECK(contact_clusters(pair, 2 * 0.625 * (1 + 1e-9)) == std::vector<std::uint32_t>{0, 1});
}
