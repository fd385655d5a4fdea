// The ED event queue (event_queue.hpp): pops in time order, and a purge of the stale events (compact) leaves
// the order in which the live ones come out unchanged — against a sorted list, with pushes, pops and purges
// interleaved at random and about half the events stale.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "particle/ed/event_queue.hpp"

using namespace aggkit;

TEST_CASE("ed event queue: pops in time order, purges of stale events change no live event's turn", "[ed][queue]") {
  for (const bool purge : {false, true}) {
    std::mt19937_64 random(17);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    EventQueue queue;
    std::set<std::uint32_t> stale;                   // ids (in `a`) invalidated so far
    std::set<std::pair<long double, std::uint32_t>> live;  // what must come out, in order
    std::uint32_t next_id = 0;
    long double now = 0;
    std::size_t popped_live = 0, purged = 0;
    auto valid = [&](const Event& e) { return stale.count(e.a) == 0; };
    for (int round = 0; round < 20000; ++round) {
      const double r = uniform(random);
      if (r < 0.55) {  // a prediction, later than now (distinct times)
        Event e{};
        e.time = now + 1e-6 + uniform(random);
        e.a = next_id++;
        e.kind = EventKind::wall;
        queue.push(e);
        live.insert({e.time, e.a});
      } else if (r < 0.75 && !live.empty()) {  // a stamp change: a random live event goes stale
        auto it = live.begin();
        std::advance(it, std::size_t(uniform(random) * double(live.size())) % live.size());
        stale.insert(it->second);
        live.erase(it);
      } else if (r < 0.98) {  // the next live event
        while (!queue.empty() && !valid(queue.top())) queue.pop();
        if (queue.empty()) continue;
        const Event e = queue.top();
        queue.pop();
        REQUIRE(!live.empty());
        REQUIRE(e.time == live.begin()->first);  // the earliest live event, whatever was purged before
        REQUIRE(e.a == live.begin()->second);
        now = e.time;
        live.erase(live.begin());
        ++popped_live;
      } else if (purge) {
        const std::size_t before = queue.size();
        queue.compact(valid);
        purged += before - queue.size();
        REQUIRE(queue.size() == live.size());  // every stale event gone, every live one kept
      }
    }
    CHECK(popped_live > 3000);
    if (purge) CHECK(purged > 1000);
  }
}
