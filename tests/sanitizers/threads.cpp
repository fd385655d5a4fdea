// ThreadSanitizer driver for the particle engines' threads (tests/sanitizers/tsan_threads.sh builds it with
// the engines' sources under -fsanitize=thread): DEM contact forces on 2 and 3 force threads (periodic,
// friction on: tangential histories), DEM direct and Barnes–Hut gravity on 3 threads (reflecting box), TS
// cluster minimisations on 2 and 3 threads, and a DSMC ensemble of 4 realizations on 2 threads. Each threaded
// run must also equal the one-thread run bit for bit (the engines promise the same run on any thread count),
// so the driver fails on a race report (TSan's exit code) or on a difference. Exit 0: clean.
#include <cmath>
#include <cstdio>
#include <vector>

#include "particle/common/initial_state.hpp"
#include "particle/dem/dem.hpp"
#include "particle/dsmc/ensemble.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

using namespace aggkit;

namespace {

int failures = 0;

void same(const char* what, bool equal) {
  std::printf("%s: %s\n", what, equal ? "same as one thread" : "DIFFERS from one thread");
  if (!equal) ++failures;
}

std::vector<Vector3> dem_run(std::size_t threads, bool gravity, bool tree) {
  const std::size_t n = 600;
  const double radius = 0.5, mass = 1.0, contact_time = 0.05;
  const double side = box_side_for_volume_fraction(3, n, radius, 0.2);
  const Box box{3, {side, side, side}, gravity ? Boundary::reflecting : Boundary::periodic};
  ParticleStart start;
  start.positions = lattice_positions(box, n, radius);
  start.velocities = initial_velocities(3, n, VelocityLaw::uniform_components, 1.0, 5);
  start.radii.assign(n, radius);
  start.masses.assign(n, mass);
  DemSettings s;
  s.stiffness = (mass / 2) * (M_PI * M_PI + 0.1) / (contact_time * contact_time);
  s.damping = 0.5;
  s.dt = contact_time / 50;
  s.friction = gravity ? 0.0 : 0.5;
  s.gravity = gravity;
  s.G = 0.01;
  s.tree = tree;
  s.force_threads = threads;
  Dem dem(box, std::move(start), s);
  for (int k = 0; k < 300; ++k) dem.step();
  return dem.positions();
}

std::vector<Vector3> ts_run(std::size_t threads) {
  const std::size_t n = 2000;
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(2, n, radius, 0.3);
  const Box box{2, {side, side, 0.0}, Boundary::reflecting};
  TsSettings settings;
  settings.threads = threads;
  TimeSteppingAggregation ts(box, radius, lattice_positions(box, n, radius),
                             initial_velocities(2, n, VelocityLaw::fixed_speed, 1.0, 3), settings);
  ts.advance(30.0, 1);
  return ts.positions();
}

std::vector<double> dsmc_run(std::size_t threads) {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(0.1);
  model.size = 1000;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  dsmc::Options options;
  options.particles = 20000;
  options.runs = 4;
  options.threads = threads;
  dsmc::Ensemble ensemble(model, options, 5.0);
  std::vector<double> m2;
  for (const auto& snapshot : ensemble.advance_to(5.0)) m2.push_back(snapshot.moment(2.0));
  return m2;
}

}  // namespace

int main() {
  const auto dem1 = dem_run(1, false, false);
  same("DEM contacts, friction, 2 force threads", dem_run(2, false, false) == dem1);
  same("DEM contacts, friction, 3 force threads", dem_run(3, false, false) == dem1);
  same("DEM direct gravity, 3 force threads", dem_run(3, true, false) == dem_run(1, true, false));
  same("DEM tree gravity, 3 force threads", dem_run(3, true, true) == dem_run(1, true, true));
  const auto ts1 = ts_run(1);
  same("TS cluster threads 2", ts_run(2) == ts1);
  same("TS cluster threads 3", ts_run(3) == ts1);
  same("DSMC ensemble of 4 on 2 threads", dsmc_run(2) == dsmc_run(1));
  return failures ? 1 : 0;
}
