// The neighbour grid reports exactly the pairs an O(N^2) search finds, periodic or not, also when the
// cutoff leaves fewer than three cells along an axis.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>

#include "analysis/neighbour_grid.hpp"
#include "analysis/particle_configuration.hpp"

using namespace aggkit;

namespace {
std::set<std::pair<std::size_t, std::size_t>> brute_force(const ParticleConfiguration& c, double cutoff) {
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < c.positions.size(); ++i)
    for (std::size_t j = i + 1; j < c.positions.size(); ++j)
      if (squared_norm(separation(c, c.positions[i], c.positions[j])) <= cutoff * cutoff) pairs.emplace(i, j);
  return pairs;
}
}  // namespace

TEST_CASE("neighbour grid: same pairs as the O(N^2) search") {
  std::mt19937_64 rng(7);
  for (int dimension : {2, 3})
    for (bool periodic : {false, true})
      for (double cutoff : {0.3, 1.7, 4.5}) {  // many cells, a few, fewer than three per axis
        ParticleConfiguration c;
        c.dimension = dimension;
        c.radius = 0.1;
        c.periodic = periodic;
        c.box = {10, 8, 9};
        std::uniform_real_distribution<double> u(0, 1);
        for (int i = 0; i < 400; ++i) c.positions.push_back({10 * u(rng), 8 * u(rng), dimension == 3 ? 9 * u(rng) : 0});
        NeighbourGrid grid(c.positions, dimension, cutoff, c.box, periodic);
        std::set<std::pair<std::size_t, std::size_t>> found;
        std::size_t visits = 0, wrong_separations = 0;
        grid.for_each_pair([&](std::size_t i, std::size_t j, const std::array<double, 3>& d, double d2) {
          ++visits;
          found.emplace(std::min(i, j), std::max(i, j));
          const auto expected = separation(c, c.positions[i], c.positions[j]);
          wrong_separations += std::abs(d2 - squared_norm(expected)) > 1e-12 * (1 + d2) ||
                               std::abs(d[0] - expected[0]) > 1e-12 || std::abs(d[1] - expected[1]) > 1e-12;
        });
        INFO("dimension " << dimension << " periodic " << periodic << " cutoff " << cutoff);
        CHECK(wrong_separations == 0);
        CHECK(visits == found.size());  // no pair twice
        CHECK(found.size() > 10);       // not vacuous
        CHECK(found == brute_force(c, cutoff));
      }
}

TEST_CASE("neighbour grid: a sparse set does not allocate a cell per cutoff length") {
  std::vector<std::array<double, 3>> far{{0, 0, 0}, {1e6, 1e6, 0}, {1, 0, 0}};
  NeighbourGrid grid(far, 2, 1.5);
  CHECK(grid.cell_count() <= 2 * far.size() + 8);
  std::size_t pairs = 0;
  grid.for_each_pair([&](std::size_t, std::size_t, const auto&, double) { ++pairs; });
  CHECK(pairs == 1);
}
