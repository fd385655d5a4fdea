// Elastic hard discs/spheres (the thermalisation stage, sticking off): collisions per second, counting
// collisions only. Reference: a general-purpose event-driven MD code reaches 2.2e4 collisions/s
// (2-D, ν = 0.01, N = 1e6) and 5e4 (3-D, ν = 0.25, N = 1e6) on one core; the target is 10x those.
//   bench_ed_elastic DIM NU COLLISIONS_PER_PARTICLE N1 [N2 ...] [--per-cell P] [--baseline C]
// Periodic box, unit speeds with uniform directions, lattice start. The timed part starts after one
// collision per particle (the lattice start is not representative). Each N is run with the ElasticGas
// (particle/ed/elastic_gas.hpp) and, as the baseline in the same run, with the ED aggregation engine in
// elastic mode for C collisions per particle (default 0.2; 0 skips it). Prints collisions/s, the ratio,
// events per collision and the relative energy drift.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bench/ed_common.hpp"
#include "bench/figures.hpp"
#include "particle/ed/elastic_gas.hpp"

using namespace aggkit;

namespace {

struct Measured {
  double setup = 0, run = 0, collisions = 0, events = 0, crossings = 0, stale = 0, drift = 0;
  double rate() const { return collisions / run; }
};

Measured run_gas(int dimension, std::size_t n, double nu, double per_particle, double per_cell) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(dimension, n, radius, nu);
  const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, Boundary::periodic};
  auto start = std::chrono::steady_clock::now();
  const auto x = lattice_positions(box, n, radius);
  const auto v = initial_velocities(dimension, n, VelocityLaw::fixed_speed, 1.0, 1);
  auto gas = make_elastic_gas(box, radius, x, v, per_cell);
  const double e0 = gas->kinetic_energy();
  while (gas->counters().collisions < n / 2 && gas->step()) {
  }
  Measured m;
  m.setup = bench::seconds_since(start);
  const auto c0 = gas->counters();
  const auto target = c0.collisions + std::uint64_t(per_particle * double(n) / 2);
  start = std::chrono::steady_clock::now();
  while (gas->counters().collisions < target && gas->step()) {
  }
  m.run = bench::seconds_since(start);
  m.collisions = double(gas->counters().collisions - c0.collisions);
  m.events = double(gas->counters().events() - c0.events());
  m.crossings = double(gas->counters().cell_crossings - c0.cell_crossings);
  m.stale = double(gas->counters().stale_events - c0.stale_events);
  m.drift = std::abs(gas->kinetic_energy() - e0) / e0;
  return m;
}

Measured run_baseline(int dimension, std::size_t n, double nu, double per_particle) {
  auto start = std::chrono::steady_clock::now();
  auto ed = bench::make_ed(dimension, n, nu, Boundary::periodic, false);
  const double e0 = ed.kinetic_energy();
  while (ed.counters().elastic_collisions < n / 2 && ed.step()) {
  }
  Measured m;
  m.setup = bench::seconds_since(start);
  const auto c0 = ed.counters();
  const auto target = c0.elastic_collisions + std::uint64_t(per_particle * double(n) / 2);
  start = std::chrono::steady_clock::now();
  while (ed.counters().elastic_collisions < target && ed.step()) {
  }
  m.run = bench::seconds_since(start);
  m.collisions = double(ed.counters().elastic_collisions - c0.elastic_collisions);
  m.events = double(ed.counters().events() - c0.events());
  m.drift = std::abs(ed.kinetic_energy() - e0) / e0;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  double per_cell = 0, baseline = 0.2;
  std::vector<char*> args;
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--per-cell") && k + 1 < argc) per_cell = std::atof(argv[++k]);
    else if (!std::strcmp(argv[k], "--baseline") && k + 1 < argc) baseline = std::atof(argv[++k]);
    else args.push_back(argv[k]);
  }
  if (args.size() < 4) {
    std::fprintf(stderr, "usage: %s DIM NU COLLISIONS_PER_PARTICLE N1 [N2 ...] [--per-cell P] [--baseline C]\n",
                 argv[0]);
    return 2;
  }
  const int dimension = std::atoi(args[0]);
  const double nu = std::atof(args[1]);
  const double per_particle = std::atof(args[2]);
  bench::print_load();
  std::printf("# elastic, dim %d periodic nu %g, %g collisions per particle timed (baseline %g), per-cell %g\n",
              dimension, nu, per_particle, baseline, per_cell);
  std::printf("%10s %8s %10s %12s %14s %12s %10s %10s %10s %14s %8s\n", "N", "setup_s", "run_s", "collisions",
              "collisions/s", "events/coll", "cross/coll", "stale/coll", "drift", "baseline_c/s", "ratio");
  const bench::Figures figures("ed_elastic", argc, argv);
  for (std::size_t k = 3; k < args.size(); ++k) {
    const auto n = std::size_t(std::atof(args[k]));
    const Measured gas = run_gas(dimension, n, nu, per_particle, per_cell);
    Measured base;
    if (baseline > 0) base = run_baseline(dimension, n, nu, baseline);
    std::printf("%10zu %8.2f %10.2f %12.0f %14.3g %12.2f %10.2f %10.2f %10.1e %14.3g %8.1f\n", n, gas.setup, gas.run,
                gas.collisions, gas.rate(), gas.events / gas.collisions, gas.crossings / gas.collisions,
                gas.stale / gas.collisions, gas.drift, baseline > 0 ? base.rate() : 0.0,
                baseline > 0 ? gas.rate() / base.rate() : 0.0);
    std::fflush(stdout);
    const std::string case_name =
        "dim=" + std::to_string(dimension) + " nu=" + bench::Figures::text(nu) + " N=" + bench::Figures::text(double(n));
    figures.add(case_name, "collisions_per_second", gas.rate(), "1/s");
    figures.add(case_name, "energy_drift", gas.drift, "1");
  }
  bench::print_load();
}
