// TS against ED on hand-built cases: as Δt → 0 the merge order, the merge times and the final offsets
// converge to ED's; steps far longer than a diameter's flight miss no contact (substeps with contact
// detection along the flown paths), where a single flight with end-of-step overlap detection misses them.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "particle/ed/event_driven_aggregation.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

using namespace aggkit;

namespace {

// Times at which particles 1, 2, 3 join particle 0's cluster, and the final offsets x_p − x_0 (no wall is
// reached before t_end; box 40 × 40, R = 1/2).
struct History {
  std::vector<double> join;
  std::vector<Vector3> offsets;
};

const Box chain_box{2, {40, 40, 0}, Boundary::reflecting};
const std::vector<Vector3> chain_x{{10, 20, 0}, {14, 20.3, 0}, {20, 21.2, 0}, {27, 19.6, 0}};
const std::vector<Vector3> chain_v{{1, 0, 0}, {0, 0, 0}, {-0.5, 0, 0}, {-1, 0.05, 0}};
constexpr double t_end = 14.0;

template <class Engine>
History record(Engine& e, double step, const std::function<void(double)>& advance) {
  History h;
  h.join.assign(4, -1.0);
  for (double t = step; t <= t_end + 1e-12; t += step) {
    advance(t);
    for (std::uint32_t p = 1; p < 4; ++p)
      if (h.join[p] < 0 && e.cluster_of(p) == e.cluster_of(0)) h.join[p] = e.time();
  }
  const auto x = e.positions();
  for (std::uint32_t p = 0; p < 4; ++p) h.offsets.push_back(x[p] - x[0]);
  return h;
}

History ed_history() {
  EventDrivenAggregation ed(chain_box, 0.5, chain_x, chain_v);
  History h;
  h.join.assign(4, -1.0);
  while (ed.step() && ed.time() <= t_end)
    for (std::uint32_t p = 1; p < 4; ++p)
      if (h.join[p] < 0 && ed.cluster_of(p) == ed.cluster_of(0)) h.join[p] = ed.time();
  ed.advance(t_end, 1);
  const auto x = ed.positions();
  for (std::uint32_t p = 0; p < 4; ++p) h.offsets.push_back(x[p] - x[0]);
  return h;
}

History ts_history(double dt_factor, bool contact_time) {
  TsSettings s;
  s.dt_factor = dt_factor;
  s.contact_time = contact_time;
  TimeSteppingAggregation ts(chain_box, 0.5, chain_x, chain_v, s);
  History h;
  h.join.assign(4, -1.0);
  while (ts.time() < t_end && ts.clusters() > 1) {
    ts.step();
    for (std::uint32_t p = 1; p < 4; ++p)
      if (h.join[p] < 0 && ts.cluster_of(p) == ts.cluster_of(0)) h.join[p] = ts.time();
  }
  ts.advance(t_end, 1);
  const auto x = ts.positions();
  for (std::uint32_t p = 0; p < 4; ++p) h.offsets.push_back(x[p] - x[0]);
  return h;
}

}  // namespace

TEST_CASE("ts: as dt -> 0 the merge order, times and final offsets converge to ED's", "[ts][against_ed]") {
  // Every collision of the chain is binary: with contact-time merging (the default) TS is ED's dynamics
  // up to round-off at any Δt; without it (the paper's scheme: overlaps resolved by the minimisation) it
  // converges at first order.
  const History ed = ed_history();
  // The hand-built chain: 1 joins at t ≈ 3.05, 2 at ≈ 7.1, 3 later; all three by t_end.
  REQUIRE(ed.join[1] > 0);
  REQUIRE(ed.join[2] > ed.join[1]);
  REQUIRE(ed.join[3] > ed.join[2]);
  std::vector<double> errors;
  for (const double f : {0.004, 0.001, 0.00025, 0.0000625}) {
    const History ts = ts_history(f, false);
    const History exact = ts_history(f, true);
    for (std::uint32_t p = 1; p < 4; ++p) CHECK(norm(exact.offsets[p] - ed.offsets[p]) < 1e-9);
    const double dt = f * 40.0 * 2.0;  // the longest step of the law: 2 Δt(0), Δt(0) = f L / max|V|
    double offset_error = 0;
    CHECK(ts.join[1] < ts.join[2]);  // the same merge order
    CHECK(ts.join[2] < ts.join[3]);
    for (std::uint32_t p = 1; p < 4; ++p) {
      INFO("dt_factor " << f << ", particle " << p << ": joins at " << ts.join[p] << " (ED " << ed.join[p] << ")");
      // A contact is found at the end of the step that contains it; an earlier merge found late shifts the
      // cluster by O(Δt), so a later contact can come up to a step early as well.
      CHECK(std::abs(ts.join[p] - ed.join[p]) <= 2 * dt);
      offset_error = std::max(offset_error, norm(ts.offsets[p] - ed.offsets[p]));
    }
    INFO("dt_factor " << f << ": largest offset error " << offset_error);
    // First order in Δt: a merge found up to one step late is resolved from an overlap of up to |ΔV| Δt
    // (|ΔV| ≤ 1.2 here), so the offsets are off by O(Δt); measured 0.27–0.48 of the longest step.
    CHECK(offset_error <= dt);
    errors.push_back(offset_error);
  }
  // Over a 64-fold reduction of Δt the error shrinks (measured 0.085 → 0.0020, 42-fold); the phase of each
  // contact within its step makes single halvings non-monotone, so the ends are compared.
  CHECK(errors.back() <= errors.front() / 16);
}

TEST_CASE("ts: a step of many diameters misses no contact (substeps), as ED", "[ts][against_ed][substeps]") {
  // Five head-on lanes, impact parameters b / 2R = 0, 0.5, 0.9, 0.99 (contacts) and 1.01 (a miss); each
  // pair meets at t ≈ 9.5, long before any wall. ED: 4 merges. TS with one step of 15 time units (the
  // discs fly 15 diameters in it).
  const Box box{2, {40, 40, 0}, Boundary::reflecting};
  std::vector<Vector3> x, v;
  const double bs[] = {0.0, 0.5, 0.9, 0.99, 1.01};
  for (int k = 0; k < 5; ++k) {
    x.push_back({10, 5.0 + 6.0 * k, 0});
    x.push_back({30, 5.0 + 6.0 * k + bs[k], 0});
    v.push_back({1, 0, 0});
    v.push_back({-1, 0, 0});
  }
  EventDrivenAggregation ed(box, 0.5, x, v);
  ed.advance(15.0, 1);
  REQUIRE(ed.counters().merges == 4);
  TsSettings s;
  s.dt_factor = 15.0 / 40.0;  // Δt(0) = dt_factor L / max|V| = 15 (10 clusters of 10: the law's factor is 1)
  for (const bool contact_time : {true, false}) {  // binary merges at contact, or all by the minimisation
    INFO("contact_time " << contact_time);
    s.contact_time = contact_time;
    TimeSteppingAggregation ts(box, 0.5, x, v, s);
    REQUIRE(ts.time_step() == Approx(15.0));
    ts.step();
    CHECK(ts.counters().merges == ed.counters().merges);
    CHECK(ts.counters().substeps == 60);  // 15 diameters in flights of at most 0.25
    CHECK(ts.largest_relative_overlap() <= TimeSteppingAggregation::same_cluster_tolerance);
    for (int k = 0; k < 4; ++k) CHECK(ts.cluster_of(2 * k) == ts.cluster_of(2 * k + 1));
    CHECK(ts.cluster_of(8) != ts.cluster_of(9));
  }
  s.contact_time = true;
  // One flight of 15 diameters: contact-time merging rewinds each pair to its contact, so even then the
  // pairs end touching; without it the swept test links the four pairs 10 diameters apart, beyond the
  // attraction range: the configuration is wrong.
  s.substep_displacement = 1e6;
  TimeSteppingAggregation one_flight(box, 0.5, x, v, s);
  one_flight.step();
  CHECK(one_flight.counters().substeps == 1);
  CHECK(one_flight.counters().merges == 4);
  CHECK(std::abs(norm(one_flight.positions()[1] - one_flight.positions()[0]) - 1.0) < 1e-9);
  s.contact_time = false;
  TimeSteppingAggregation one_flight_overlaps(box, 0.5, x, v, s);
  one_flight_overlaps.step();
  CHECK(norm(one_flight_overlaps.positions()[1] - one_flight_overlaps.positions()[0]) > 9.0);
  // Substeps of 0.25 diameters with end-of-flight overlaps only would still miss the grazing lane
  // (overlap chord 2R √(1 − 0.99²) = 0.28 R against a relative flight of R per substep): the swept test
  // finds it (lane 3 merged above).
}
