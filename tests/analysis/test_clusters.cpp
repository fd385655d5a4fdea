// Clusters by union–find over contacts, their size distribution, and unwrapping across periodic walls.
#include <catch2/catch.hpp>

#include <numeric>
#include <random>

#include "analysis/clusters.hpp"
#include "analysis/input_error.hpp"
#include "analysis/shape.hpp"
#include "tests/analysis/known_shapes.hpp"

using namespace aggkit;

namespace {
ParticleConfiguration configuration(std::vector<std::array<double, 3>> positions, bool periodic,
                                    std::array<double, 3> box = {10, 10, 10}) {
  ParticleConfiguration c;
  c.radius = 0.5;
  c.box = box;
  c.periodic = periodic;
  c.positions = std::move(positions);
  return c;
}
}  // namespace

TEST_CASE("clusters: union-find joins sets and counts components") {
  UnionFind sets(6);
  CHECK(sets.components() == 6);
  CHECK(sets.unite(0, 1));
  CHECK(sets.unite(2, 3));
  CHECK(sets.unite(1, 3));
  CHECK_FALSE(sets.unite(0, 2));  // already joined
  CHECK(sets.components() == 3);
  CHECK(sets.find(0) == sets.find(3));
  CHECK(sets.find(4) != sets.find(5));
  CHECK(sets.size_of(2) == 4);
}

TEST_CASE("clusters: labels by first appearance, contacts inclusive of the contact distance") {
  // 0-1 and 1-5 touch exactly (distance 1 = 2R), 2 is alone, 3-4 overlap slightly.
  const auto c = configuration({{1, 1, 0}, {2, 1, 0}, {5, 5, 0}, {8, 8, 0}, {8, 8.9, 0}, {3, 1, 0}}, false);
  const auto labels = contact_clusters(c, 2 * c.radius);
  CHECK(labels == std::vector<std::uint32_t>{0, 0, 1, 2, 2, 0});
  CHECK(cluster_sizes(labels) == std::vector<std::size_t>{3, 1, 2});
  CHECK(mean_cluster_size(cluster_sizes(labels)) == Approx(2.0));
  const auto members = cluster_members(labels);
  CHECK(members[0] == std::vector<std::size_t>{0, 1, 5});
}

TEST_CASE("clusters: contacts across a periodic boundary join clusters (minimum image)") {
  // 0 at x = 0.2 and 1 at x = 9.4 are 0.8 apart through the wall at x = 0 (10 apart in the box: 9.2);
  // 2 at the corner (9.7, 9.7) touches 3 at (0.1, 0.1) through both walls (distance 0.57).
  std::vector<std::array<double, 3>> p{{0.2, 5, 0}, {9.4, 5, 0}, {9.7, 9.7, 0}, {0.1, 0.1, 0}, {5, 5, 0}};
  const auto periodic = contact_clusters(configuration(p, true), 1.0);
  CHECK(periodic == std::vector<std::uint32_t>{0, 0, 1, 1, 2});
  const auto walled = contact_clusters(configuration(p, false), 1.0);
  CHECK(walled == std::vector<std::uint32_t>{0, 1, 2, 3, 4});
}

TEST_CASE("clusters: agree with an O(N^2) union-find on a random periodic gas") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 10);
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 300; ++i) p.push_back({u(rng), u(rng), u(rng)});
  auto c = configuration(p, true);
  c.dimension = 3;
  const auto labels = contact_clusters(c, 1.2);
  UnionFind brute(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if (squared_norm(separation(c, p[i], p[j])) <= 1.2 * 1.2) brute.unite(i, j);
  CHECK(cluster_sizes(labels).size() == brute.components());
  std::size_t disagreements = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) disagreements += (labels[i] == labels[j]) != (brute.find(i) == brute.find(j));
  CHECK(disagreements == 0);
  CHECK(brute.components() < 250);  // the contacts do join particles (the check is not vacuous)
}

TEST_CASE("clusters: the size distribution is a distribution over clusters") {
  const std::vector<std::size_t> sizes{3, 1, 1, 2, 0, 1, 3};  // label 4 has no members: not a cluster
  const auto d = size_distribution(sizes);
  CHECK(d.size == std::vector<std::size_t>{1, 2, 3});
  CHECK(d.pdf == std::vector<double>{0.5, 1.0 / 6, 2.0 / 6});
  CHECK(std::accumulate(d.pdf.begin(), d.pdf.end(), 0.0) == Approx(1.0).epsilon(1e-15));
  CHECK(d.cdf.back() == 1.0);
  CHECK(d.cdf[1] == Approx(4.0 / 6));
  CHECK(mean_cluster_size(sizes) == Approx(11.0 / 6));
  CHECK(size_distribution(std::vector<std::size_t>{}).size.empty());
  CHECK(mean_cluster_size(std::vector<std::size_t>{}) == 0.0);
}

TEST_CASE("clusters: a chain wrapped through the periodic corner is unwrapped into a straight chain") {
  // Ten touching particles along the diagonal starting near (9, 9), spacing 2R/sqrt(2) per axis: they
  // cross both walls. Unwrapped, consecutive particles are 2R apart and all lie on one straight line,
  // so the gyration tensor has one non-zero eigenvalue, that of a line of 10 points: Σ (i - 4.5)² d²/10.
  const double step = 1.0 / std::sqrt(2.0);
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 10; ++i) {
    const double x = std::fmod(9.0 + step * i, 10.0);
    p.push_back({x, x, 0});
  }
  const auto c = configuration(p, true);
  std::vector<std::size_t> members(10);
  std::iota(members.begin(), members.end(), std::size_t{0});
  const auto unwrapped = unwrap_cluster(c, members, 1.0 + 1e-9);
  for (int i = 1; i < 10; ++i) {
    CHECK(unwrapped[i][0] - unwrapped[i - 1][0] == Approx(step).epsilon(1e-12));
    CHECK(unwrapped[i][1] - unwrapped[i - 1][1] == Approx(step).epsilon(1e-12));
  }
  const Gyration g = gyration(unwrapped, 2);
  CHECK(g.eigenvalues[0] == Approx(82.5 / 10).epsilon(1e-12));  // Σ_{i=0}^{9} (i - 4.5)² = 82.5, d = 1
  CHECK(g.eigenvalues[1] == Approx(0).margin(1e-12));
  // The wrapped positions, taken at face value, are spread over the box instead.
  CHECK(std::abs(gyration(p, 2).eigenvalues[0] - 8.25) > 1.0);
  // The same chain plus two loose particles: it is the largest cluster, returned unwrapped.
  auto with_loose = c;
  with_loose.positions.insert(with_loose.positions.begin(), {{5, 2, 0}, {2, 5, 0}});
  const auto labels = contact_clusters(with_loose, 1.0 + 1e-9);
  CHECK(largest_cluster(with_loose, labels, 1.0 + 1e-9) == unwrapped);
  // Without periodicity the positions are returned as they are.
  CHECK(unwrap_cluster(configuration(p, false), members, 1.0) == p);
}

TEST_CASE("clusters: unwrapping members that are not one cluster is an error") {
  const auto c = configuration({{1, 1, 0}, {5, 5, 0}}, true);
  const std::vector<std::size_t> members{0, 1};
  CHECK_THROWS_AS(unwrap_cluster(c, members, 1.0), InputError);
  const std::vector<std::size_t> outside{0, 7};
  CHECK_THROWS_AS(unwrap_cluster(c, outside, 1.0), InputError);
}

TEST_CASE("clusters: kinetic energy and bad input") {
  const std::vector<double> mass{1, 2};
  const std::vector<std::array<double, 3>> v{{1, 2, 2}, {0, 0, 3}};
  CHECK(kinetic_energy(mass, v) == Approx(0.5 * 9 + 0.5 * 2 * 9));
  CHECK_THROWS_AS(kinetic_energy(std::vector<double>{1}, v), InputError);
  auto c = configuration({{1, 1, 0}}, false);
  CHECK_THROWS_AS(contact_clusters(c, 0.0), InputError);
  c.dimension = 4;
  CHECK_THROWS_AS(contact_clusters(c, 1.0), InputError);
  c.dimension = 2;
  c.periodic = true;
  c.box = {10, 0, 0};
  CHECK_THROWS_WITH(contact_clusters(c, 1.0), Catch::Contains("box[1]"));
}
