// Whole TS runs to one cluster, checked after every step: the mean link measure of every minimisation
// ≤ ε_c (when it converged), no pair overlapping by more than 1 % of 2R, N − 1 merges, momentum plus
// wall impulse conserved to round-off, kinetic energy never increasing; results independent of the
// number of cluster threads.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "particle/common/checkpoint.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

using namespace aggkit;

namespace {

// A whole-run case: lattice start of `count` spheres at volume fraction `nu`.
struct Case {
  int dimension;
  std::size_t count;
  double nu;
  Boundary boundary;
};

TimeSteppingAggregation make_run(int dimension, std::size_t count, double nu, Boundary boundary, double dt_factor,
                                 std::size_t threads = 1, bool contact_time = true, bool quiet_flights = true,
                                 bool near_recheck = true, bool local_detection = true) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(dimension, count, radius, nu);
  const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, boundary};
  TsSettings settings;
  settings.dt_factor = dt_factor;
  settings.threads = threads;
  settings.contact_time = contact_time;
  settings.quiet_flights = quiet_flights;
  settings.near_recheck = near_recheck;
  settings.local_detection = local_detection;
  return TimeSteppingAggregation(box, radius, lattice_positions(box, count, radius),
                                 initial_velocities(dimension, count, VelocityLaw::fixed_speed, 1.0, 7), settings);
}

// Steps `run` and `reference` together until the reference holds one cluster (at most 20 000 steps).
void step_together(TimeSteppingAggregation& run, TimeSteppingAggregation& reference) {
  while (reference.clusters() > 1 && reference.counters().steps < 20000) {
    run.step();
    reference.step();
  }
}

// The same run to the bit: steps, merges, minimisation iterations, positions and wall impulse.
void check_same_run(const TimeSteppingAggregation& run, const TimeSteppingAggregation& reference) {
  CHECK(run.counters().steps == reference.counters().steps);
  CHECK(run.counters().merges == reference.counters().merges);
  CHECK(run.counters().minimisation_iterations == reference.counters().minimisation_iterations);
  CHECK(run.positions() == reference.positions());
  CHECK(run.wall_impulse() == reference.wall_impulse());
}

void check_whole_run(TimeSteppingAggregation ts) {
  const Vector3 p0 = ts.momentum() + ts.wall_impulse();
  double scale = 0;
  for (const Vector3& v : ts.velocities()) scale += norm(v);
  double energy = ts.kinetic_energy(), worst_relative = 0;
  std::uint64_t caps = 0;
  while (ts.clusters() > 1 && ts.counters().steps < 100000) {
    ts.step();
    if (ts.counters().iteration_cap_hits == caps) CHECK(ts.last_mean_link_measure() <= 1e-2);
    caps = ts.counters().iteration_cap_hits;
    worst_relative = std::max(worst_relative, ts.largest_relative_overlap());
    const double e = ts.kinetic_energy();
    REQUIRE(e <= energy * (1 + 1e-13));
    energy = e;
  }
  INFO("steps " << ts.counters().steps << ", minimisations " << ts.counters().minimisations << ", cap hits " << caps
                << ", worst relative overlap " << worst_relative);
  CHECK(ts.clusters() == 1);
  CHECK(ts.counters().merges == ts.particles() - 1);
  CHECK(worst_relative <= TimeSteppingAggregation::same_cluster_tolerance);
  CHECK(norm(ts.momentum() + ts.wall_impulse() - p0) <= 1e-12 * scale);
  CHECK(caps <= ts.counters().minimisations / 50);
}

}  // namespace

TEST_CASE("ts: 2-D reflecting run to one cluster", "[ts][whole_run]") {
  check_whole_run(make_run(2, 225, 0.2, Boundary::reflecting, 0.005));
}

TEST_CASE("ts: 2-D periodic run to one cluster", "[ts][whole_run]") {
  check_whole_run(make_run(2, 196, 0.1, Boundary::periodic, 0.005));
}

TEST_CASE("ts: 3-D reflecting and periodic runs to one cluster", "[ts][whole_run]") {
  check_whole_run(make_run(3, 125, 0.1, Boundary::reflecting, 0.01));
  check_whole_run(make_run(3, 125, 0.1, Boundary::periodic, 0.01));
}

TEST_CASE("ts: runs with every contact resolved by the minimisation (contact_time off), 2-D and 3-D", "[ts][whole_run]") {
  check_whole_run(make_run(2, 225, 0.2, Boundary::reflecting, 0.005, 1, false));
  check_whole_run(make_run(3, 125, 0.1, Boundary::periodic, 0.01, 1, false));
}

TEST_CASE("ts: two cluster threads give the same run as one", "[ts][threads]") {
  auto one = make_run(2, 400, 0.2, Boundary::reflecting, 0.01, 1);
  auto two = make_run(2, 400, 0.2, Boundary::reflecting, 0.01, 2);
  for (int s = 0; s < 60; ++s) {
    one.step();
    two.step();
  }
  CHECK(one.clusters() == two.clusters());
  CHECK(one.positions() == two.positions());
  CHECK(one.counters().minimisation_iterations == two.counters().minimisation_iterations);
}

TEST_CASE("ts: contact detection split over two threads gives the same run as one", "[ts][threads]") {
  // 20 000 discs at ν = 0.3: about 23 000 detection cells, above the size at which the pass is split.
  auto one = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 1);
  auto two = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 2);
  for (int s = 0; s < 30; ++s) {
    one.step();
    two.step();
  }
  CHECK(one.counters().merges > 100);
  CHECK(one.clusters() == two.clusters());
  CHECK(one.positions() == two.positions());
}

TEST_CASE("ts: contact-time merges spread over two threads give the same run as one, to one cluster", "[ts][threads]") {
  // 5000 discs to one cluster: the late flights merge clusters of thousands of spheres, above the size at
  // which the moves of a flight's merged clusters are spread over the workers (the merges, reflections and
  // cell moves stay in key order).
  auto one = make_run(2, 5000, 0.3, Boundary::reflecting, 0.005, 1);
  auto two = make_run(2, 5000, 0.3, Boundary::reflecting, 0.005, 2);
  while (one.clusters() > 1 && one.counters().steps < 20000) {
    one.step();
    two.step();
  }
  CHECK(one.clusters() == 1);
  CHECK(two.clusters() == 1);
  CHECK(one.counters().contact_time_merges == two.counters().contact_time_merges);
  CHECK(one.counters().minimisation_iterations == two.counters().minimisation_iterations);
  CHECK(one.positions() == two.positions());
  CHECK(one.wall_impulse() == two.wall_impulse());
}

TEST_CASE("ts: quiet flights (detection skipped within a safe time) give the same run as detecting every flight",
          "[ts][quiet]") {
  // The safe time is a proof that a skipped pass would have found nothing: the runs must agree to the
  // bit, through the end phase (few slow clusters: most flights quiet), with both kinds of walls, in 2-D
  // and 3-D.
  for (const Case k : {Case{2, 400, 0.3, Boundary::reflecting}, Case{2, 300, 0.1, Boundary::periodic},
                       Case{3, 216, 0.2, Boundary::reflecting}, Case{3, 125, 0.1, Boundary::periodic}}) {
    auto quiet = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01);
    auto every = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01, 1, true, false, true, false);
    step_together(quiet, every);
    INFO("dimension " << k.dimension << ", N " << k.count);
    CHECK(every.counters().quiet_flights == 0);
    CHECK(quiet.counters().quiet_flights > 0);  // the skipping path is taken
    check_same_run(quiet, every);
  }
}

TEST_CASE("ts: re-checking only the spheres that can meet another cluster after contact-time merges gives the same run",
          "[ts][near]") {
  // The nearest other-cluster distance of the pass and the displacements of the merge prove that the
  // spheres left out find nothing: the runs must agree to the bit, to one cluster, with both kinds of
  // walls, in 2-D and 3-D; and over 30 steps of 20 000 discs with 2 threads (the distances then gathered
  // from the workers' cells, and those of other workers' cells applied after the pass).
  for (const Case k : {Case{2, 900, 0.3, Boundary::reflecting}, Case{2, 400, 0.2, Boundary::periodic},
                       Case{3, 343, 0.2, Boundary::reflecting}, Case{3, 216, 0.1, Boundary::periodic}}) {
    auto near = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01);
    auto all = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01, 1, true, true, false);
    step_together(near, all);
    INFO("dimension " << k.dimension << ", N " << k.count);
    CHECK(all.clusters() == 1);
    CHECK(near.counters().contact_time_merges > 0);
    // The filter leaves spheres out (else the test shows nothing).
    CHECK(near.counters().rechecked_spheres < all.counters().rechecked_spheres / 2);
    check_same_run(near, all);
  }
  auto near = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 2);
  auto all = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 2, true, true, false);
  for (int s = 0; s < 30; ++s) {
    near.step();
    all.step();
  }
  CHECK(near.counters().contact_time_merges > 100);
  CHECK(near.counters().rechecked_spheres < all.counters().rechecked_spheres);
  CHECK(near.positions() == all.positions());
}

TEST_CASE("ts: local detection (only the spheres whose safe time ran out examined) gives the same run as examining every sphere, on one and two threads",
          "[ts][local]") {
  // The per-sphere safe times and the stamps of changed clusters prove that the spheres left out find
  // nothing: the runs must agree to the bit, to one cluster, with both kinds of walls, in 2-D and 3-D, and
  // over 60 steps of 20 000 discs with 2 threads (the local passes then split over the workers).
  for (const Case k : {Case{2, 900, 0.3, Boundary::reflecting}, Case{2, 400, 0.2, Boundary::periodic},
                       Case{3, 343, 0.2, Boundary::reflecting}, Case{3, 216, 0.1, Boundary::periodic}}) {
    auto local = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01);
    auto full = make_run(k.dimension, k.count, k.nu, k.boundary, 0.01, 1, true, true, true, false);
    step_together(local, full);
    INFO("dimension " << k.dimension << ", N " << k.count);
    CHECK(full.clusters() == 1);
    CHECK(full.counters().local_passes == 0);
    // The local path is taken and examines fewer spheres (else the test shows nothing).
    CHECK(local.counters().local_passes > 10);
    CHECK(local.counters().examined_spheres < full.counters().examined_spheres * 3 / 4);
    check_same_run(local, full);
  }
  auto local = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 2);
  auto full = make_run(2, 20000, 0.3, Boundary::reflecting, 0.002, 2, true, true, true, false);
  for (int s = 0; s < 60; ++s) {
    local.step();
    full.step();
  }
  CHECK(local.counters().local_passes > 5);
  CHECK(local.counters().merges == full.counters().merges);
  CHECK(local.positions() == full.positions());
}

TEST_CASE("ts: quiet flights are logged and replayed: wall bounces, reads and checkpoints in a quiet stretch change nothing",
          "[ts][quiet]") {
  // Five small clusters-to-be in a large box, 2-D and 3-D: long quiet stretches in which clusters bounce off
  // the walls (brought up to date and reflected there, the others only logged). Against a run detecting every
  // flight (every flight applied to every sphere): the same run to the bit, with a third run whose positions
  // are read every 7th step (each read brings every sphere up to date mid-stretch) and a fourth restored
  // from a checkpoint taken mid-stretch.
  for (const int dimension : {2, 3}) {
    const double side = 40;
    const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, Boundary::reflecting};
    std::vector<Vector3> x, v;
    for (int k = 0; k < 5; ++k) {
      x.push_back({5.0 + 7.0 * k, 4.0 + 6.5 * k, dimension == 3 ? 30.0 - 5.0 * k : 0.0});
      v.push_back({std::cos(1.3 * k + 0.4), std::sin(1.3 * k + 0.4), dimension == 3 ? 0.3 * (k - 2) : 0.0});
    }
    TsSettings quiet_settings, every_settings;
    quiet_settings.dt_factor = every_settings.dt_factor = 0.002;
    every_settings.quiet_flights = false;
    TimeSteppingAggregation quiet(box, 0.5, x, v, quiet_settings), every(box, 0.5, x, v, every_settings),
        read(box, 0.5, x, v, quiet_settings), restored(box, 0.5, x, v, quiet_settings);
    std::string saved;
    for (int s = 0; s < 3000; ++s) {
      quiet.step();
      every.step();
      read.step();
      if (s % 7 == 3) static_cast<void>(read.positions());  // a read brings every sphere up to date mid-stretch
      if (s == 1500) {
        StateWriter out;
        quiet.save(out);
        saved = out.take();
      }
    }
    StateReader in(saved);
    restored.restore(in);
    while (restored.counters().steps < quiet.counters().steps) restored.step();
    INFO("dimension " << dimension);
    CHECK(quiet.counters().quiet_flights > quiet.counters().substeps / 2);  // mostly quiet
    CHECK(quiet.counters().wall_contacts > 10);                              // bounces in quiet stretches
    CHECK(quiet.counters().wall_contacts == every.counters().wall_contacts);
    CHECK(quiet.positions() == every.positions());
    CHECK(quiet.wall_impulse() == every.wall_impulse());
    CHECK(read.positions() == every.positions());
    CHECK(restored.positions() == every.positions());
    CHECK(restored.wall_impulse() == every.wall_impulse());
  }
}

TEST_CASE("ts: a start with overlaps is refused naming particles.initial", "[ts][input]") {
  const Box box{2, {10, 10, 0}, Boundary::reflecting};
  const std::vector<Vector3> x{{2, 2, 0}, {2.5, 2, 0}}, v{{1, 0, 0}, {-1, 0, 0}};
  CHECK_THROWS_WITH(TimeSteppingAggregation(box, 0.5, x, v, TsSettings{}), Catch::Contains("particles.initial"));
}

TEST_CASE("ts: two discs in a head-on collision merge once, momentum conserved, touching", "[ts][few]") {
  const Box box{2, {20, 20, 0}, Boundary::reflecting};
  const std::vector<Vector3> x{{5, 10, 0}, {8, 10.3, 0}}, v{{1, 0, 0}, {-0.5, 0, 0}};
  TsSettings settings;
  settings.dt_factor = 0.002;
  TimeSteppingAggregation ts(box, 0.5, x, v, settings);
  ts.advance(4.0, 1);
  REQUIRE(ts.clusters() == 1);
  CHECK(ts.cluster_velocity(0)[0] == Approx(0.25).epsilon(1e-14));
  CHECK(std::abs(norm(ts.positions()[1] - ts.positions()[0]) - 1.0) < 1e-3);
  // ED: contact at t = (3 − √(1 − 0.09)) / 1.5; TS merges in the step that contains it.
  const double contact = (3.0 - std::sqrt(1.0 - 0.09)) / 1.5;
  CHECK(ts.time() >= contact);
  CHECK(ts.time() <= contact + 2 * ts.time_step());
}

TEST_CASE("ts: a contact-time merge that stops a disc on a third one links the third in the same flight", "[ts][few][near]") {
  // A and B meet head on at t = 0.45, in the flight (0.4, 0.6]; merged there, they stop. C comes down onto
  // the place where A stops: at the end of the flight it overlaps A's stopped position by 0.005, while over
  // the swept paths of the pass (A flying on to x = 10.6) it stayed 1.006 from A. Only the re-check of the
  // merged spheres finds the pair in that flight; left to the next pass, C would be linked a flight later.
  const Box box{2, {40, 40, 0}, Boundary::reflecting};
  const std::vector<Vector3> x{{10, 10, 0}, {11.9, 10, 0}, {10.45, 11.295, 0}}, v{{1, 0, 0}, {-1, 0, 0}, {0, -0.5, 0}};
  for (const bool near : {true, false}) {
    TsSettings settings;
    settings.dt_factor = 0.005;  // Δt(0) = 0.2, one flight per step (≤ 0.25 = 2R/4): flights end at 0.2, 0.4, 0.6
    settings.near_recheck = near;
    TimeSteppingAggregation ts(box, 0.5, x, v, settings);
    ts.step();
    ts.step();
    REQUIRE(ts.clusters() == 3);
    ts.step();
    INFO("near re-check " << near);
    REQUIRE(ts.time() == Approx(0.6).epsilon(1e-12));
    CHECK(ts.counters().substeps == 3);
    CHECK(ts.counters().contact_time_merges == 1);
    CHECK(ts.counters().rechecked_spheres >= 1);
    CHECK(ts.clusters() == 1);  // C linked in the flight of the merge
    CHECK(ts.largest_relative_overlap() < 1e-2);
  }
}
