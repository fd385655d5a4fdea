// The event calendar (particle/common/tournament_tree.hpp) against a brute-force scan: after every change
// the top is the earliest slot, and each subtree winner is the earliest of its slot range.
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "particle/common/tournament_tree.hpp"

using namespace aggkit;

TEST_CASE("tournament tree: top and subtree winners agree with a scan", "[common][tournament_tree]") {
  for (std::size_t n : {1u, 7u, 16u, 100u, 1000u}) {
    TournamentTree tree(n);
    std::vector<double> t(n, TournamentTree::never);
    CHECK(tree.top_time() == TournamentTree::never);
    std::mt19937_64 rng(n);
    std::uniform_real_distribution<double> u(0.0, 10.0);
    for (int step = 0; step < 4000; ++step) {
      const auto slot = std::uint32_t(rng() % n);
      // Mostly later times (as events are processed), sometimes earlier ones, sometimes "never".
      const double value = rng() % 10 == 0 ? TournamentTree::never : u(rng);
      t[slot] = value;
      tree.set(slot, value);
      std::size_t best = 0;
      for (std::size_t s = 1; s < n; ++s)
        if (t[s] < t[best]) best = s;
      REQUIRE(tree.top_time() == t[best]);
      if (t[best] != TournamentTree::never) REQUIRE(t[tree.top_slot()] == t[best]);
    }
    // Each reported subtree winner holds the earliest time of the slot range it stands for (blocks of
    // `block` slots, a power-of-two number of block leaves split evenly between the subtrees).
    std::size_t leaves = 1;
    while (leaves * TournamentTree::block < n) leaves *= 2;
    const std::size_t depth = 2, subtrees = std::min<std::size_t>(std::size_t(1) << depth, leaves);
    const std::size_t span = leaves / subtrees * TournamentTree::block;
    std::vector<double> expected;
    for (std::size_t k = 0; k < subtrees; ++k) {
      double m = TournamentTree::never;
      for (std::size_t s = k * span; s < std::min(n, (k + 1) * span); ++s) m = std::min(m, t[s]);
      if (m != TournamentTree::never) expected.push_back(m);
    }
    std::vector<double> got;
    tree.for_each_subtree_winner(int(depth), [&](std::uint32_t slot) { got.push_back(t[slot]); });
    CHECK(got == expected);
    tree.shift_times(1.0);
    std::size_t best = 0;
    for (std::size_t s = 1; s < n; ++s)
      if (t[s] < t[best]) best = s;
    CHECK(tree.top_time() == t[best] - 1.0);
  }
}
