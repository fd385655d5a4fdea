// Soak: each engine run again and again on a realistic problem for a set wall time, its invariants checked
// after every stretch of the run (not only at the end), and the process's resident memory sampled after
// every run, so that a slow leak or a rare violation shows up:
//   kinetic (CVODE)  ballistic kernel, cutoff at N = 5000, λ cycling 0.01, 0.1, 1, to t = 1000: mass M1 = 1
//                    at every output to round-off (the projected integrator keeps it; measured ≤ 6e-15 in
//                    bench/results/log/cvode-stress.md): |M1 − 1| ≤ 1e-12 = N·eps·(a factor 50 for the sums)
//   DSMC             ballistic kernel, λ = 0.01, 10^6 particles to t = 100 [Kalinov2022, Table 2]: the integer
//                    mass Σ k·count + leaked equals the mass at the last population-control event and, without
//                    halving, N(0)·2^doublings, exactly; M1 + leaked density = 1 to 1e-12 (a double sum)
//   ED               2-D periodic ballistic aggregation, N = 20000 at ν = 0.1 to one cluster [Degond2024]:
//                    total momentum conserved (periodic box, momentum-weighted merges) to 1e-10 of Σ|v|, the
//                    largest pair overlap ≤ the engine's contact round-off bound (overlap_tolerance, 1e-9)
//   TS               the same start with the time-stepping engine: momentum to 1e-10 of Σ|v|, no pair
//                    (same cluster or not) overlapping beyond the engine's tolerance: the largest 1 − |Δx|/2R ≤
//                    its same-cluster tolerance (1e-2)
//   DEM              elastic spheres (restitution 1: no dashpot, no friction), N = 4000, φ = 0.2, periodic,
//                    dt = t_c/50: total energy (kinetic + spring) within 1e-3 of E(0) at every check — velocity
//                    Verlet is symplectic, so the error stays bounded at O((ω dt)²) ≈ (π/50)² ≈ 4e-3 of the energy
//                    held in springs, itself a few % of the total at φ = 0.2 — and momentum to 1e-10 of Σ m|v|
// Memory: RSS (/proc/self/statm) after each run; the growth from the end of the first run to the largest
// later sample must stay under 10 % of the first + 16 MiB (allocator caching, not a leak, fits in that).
//   bench_soak [--seconds S per engine, default 600] [--engine kinetic|dsmc|ed|ts|dem] (repeatable; default all)
// Prints per engine: runs, checks, the worst value of each invariant against its bound, RSS first/max/last;
// exits 1 if any invariant or the memory bound is violated.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

#include "analysis/moments.hpp"
#include "bench/ed_common.hpp"
#include "bench/figures.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/dem/dem.hpp"
#include "particle/dsmc/simulation.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {

using Clock = std::chrono::steady_clock;

double rss_mib() {
  long pages_total = 0, pages_resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
    std::fclose(f);
  }
  return double(pages_resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// The worst value seen of one invariant against its bound.
struct Invariant {
  Invariant(std::string n, double b) : name(std::move(n)), bound(b) {}
  std::string name;
  double bound;
  double worst = 0;
  std::string where;
  void see(double value, const std::string& at) {
    if (!(value <= worst)) worst = value, where = at;  // NaN counts as worst
  }
  bool holds() const { return worst <= bound; }
};

struct Soak {
  explicit Soak(std::vector<Invariant> i) : invariants(std::move(i)) {}
  std::vector<Invariant> invariants;
  std::size_t runs = 0, checks = 0;
  std::vector<double> rss;  // after each run
  Invariant& operator[](const std::string& name) {
    for (auto& i : invariants)
      if (i.name == name) return i;
    std::fprintf(stderr, "soak: no invariant %s\n", name.c_str());
    std::abort();
  }
};

Vector3 absolute_momentum_scale(const std::vector<Vector3>& v) {
  double s = 0;
  for (const auto& x : v) s += norm(x);
  return {s, 0, 0};
}

// One kinetic run: λ from the cycle, outputs every 10 to t = 1000.
void kinetic_run(Soak& soak) {
  const double lambdas[] = {0.01, 0.1, 1.0};
  const double lambda = lambdas[soak.runs % 3];
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(lambda);
  model.size = 5000;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  std::vector<double> outputs;
  for (int k = 1; k <= 100; ++k) outputs.push_back(10.0 * k);
  IntegratorOptions options;
  options.max_steps = 200000;
  integrate(model, outputs, options, [&](double t, std::span<const double> n, double leaked) {
    ++soak.checks;
    soak["|M1 - 1|"].see(std::abs(moment(n, 1.0) + leaked - 1.0), "lambda " + bench::Figures::text(lambda) + " t " + bench::Figures::text(t));
  });
}

void dsmc_run(Soak& soak) {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(0.01);
  model.size = 5000;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  dsmc::Options options;
  options.particles = 1000000;
  dsmc::Simulation simulation(model, options, 1 + soak.runs, 100.0);
  for (int k = 1; k <= 100; ++k) {
    simulation.advance_to(double(k));
    ++soak.checks;
    const std::string at = "run " + std::to_string(soak.runs) + " t " + std::to_string(k);
    const auto& s = simulation.statistics();
    const bool exact = simulation.mass() == simulation.control_mass() &&
                       (s.halvings > 0 || simulation.mass() == simulation.initial_mass() << s.doublings);
    soak["integer mass off (0/1)"].see(exact ? 0.0 : 1.0, at);
    const dsmc::Snapshot snapshot = simulation.snapshot();
    soak["|M1 + leaked - 1|"].see(std::abs(snapshot.moment(1.0) + snapshot.leaked_density() - 1.0), at);
  }
}

// A 2-D periodic start at ν = 0.1, unit speeds, seed per run.
struct Start2d {
  Box box;
  double radius = 0.5;
  std::vector<Vector3> x, v;
};
Start2d start_2d(std::size_t count, std::uint64_t seed) {
  Start2d s;
  const double side = box_side_for_volume_fraction(2, count, s.radius, 0.1);
  s.box = Box{2, {side, side, 0.0}, Boundary::periodic};
  s.x = lattice_positions(s.box, count, s.radius);
  s.v = initial_velocities(2, count, VelocityLaw::fixed_speed, 1.0, seed);
  return s;
}

void ed_run(Soak& soak) {
  const Start2d s = start_2d(20000, 1 + soak.runs);
  EventDrivenAggregation ed(s.box, s.radius, s.x, s.v, /*sticking=*/true);
  const Vector3 p0 = ed.momentum();
  const double scale = absolute_momentum_scale(s.v)[0];
  for (double t = 1; ed.clusters() > 1 && t < 1e7; t *= 1.5) {
    ed.advance(t, 1);
    ++soak.checks;
    const std::string at = "run " + std::to_string(soak.runs) + " t " + bench::Figures::text(ed.time()) + " clusters " + std::to_string(ed.clusters());
    soak["|P - P0| / sum|v|"].see(norm(ed.momentum() - p0) / scale, at);
    soak["largest overlap"].see(ed.largest_overlap(), at);
  }
}

void ts_run(Soak& soak) {
  const Start2d s = start_2d(20000, 1 + soak.runs);
  TsSettings settings;
  TimeSteppingAggregation ts(s.box, s.radius, s.x, s.v, settings);
  const Vector3 p0 = ts.momentum();
  const double scale = absolute_momentum_scale(s.v)[0];
  for (double t = 1; ts.clusters() > 1 && !ts.at_rest() && t < 1e7; t *= 1.5) {
    ts.advance(t, 1);
    ++soak.checks;
    const std::string at = "run " + std::to_string(soak.runs) + " t " + bench::Figures::text(ts.time()) + " clusters " + std::to_string(ts.clusters());
    soak["|P - P0| / sum|v|"].see(norm(ts.momentum() - p0) / scale, at);
    soak["largest 1 - |dx|/2R"].see(ts.largest_relative_overlap(), at);
  }
}

void dem_run(Soak& soak) {
  const std::size_t n = 4000;
  const double radius = 0.5, mass = 1.0, contact_time = 0.02, phi = 0.2;
  const double side = box_side_for_volume_fraction(3, n, radius, phi);
  const Box box{3, {side, side, side}, Boundary::periodic};
  ParticleStart start;
  start.positions = lattice_positions(box, n, radius);
  start.velocities = initial_velocities(3, n, VelocityLaw::uniform_components, 1.0, 1 + soak.runs);
  start.radii.assign(n, radius);
  start.masses.assign(n, mass);
  const double scale = absolute_momentum_scale(start.velocities)[0];
  DemSettings settings;
  settings.stiffness = (mass / 2) * M_PI * M_PI / (contact_time * contact_time);  // e = 1: no dashpot
  settings.dt = contact_time / 50;
  Dem dem(box, std::move(start), settings);
  const double e0 = dem.total_energy();
  const Vector3 p0 = dem.momentum();
  // 20 time units (≈ 1000 contact times; each sphere collides many times), checked every 0.2.
  for (int block = 1; block <= 100; ++block) {
    for (int k = 0; k < 250; ++k) dem.step();
    ++soak.checks;
    const std::string at = "run " + std::to_string(soak.runs) + " t " + bench::Figures::text(dem.time());
    soak["|E - E0| / E0"].see(std::abs(dem.total_energy() - e0) / e0, at);
    soak["|P - P0| / sum m|v|"].see(norm(dem.momentum() - p0) / scale, at);
  }
}

struct EngineSoak {
  const char* name;
  std::vector<Invariant> invariants;
  std::function<void(Soak&)> run;
};

}  // namespace

int main(int argc, char** argv) {
  double seconds = 600;
  std::vector<std::string> wanted;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) seconds = std::atof(argv[++i]);
    else if (std::strcmp(argv[i], "--engine") == 0 && i + 1 < argc) wanted.push_back(argv[++i]);
    else {
      std::fprintf(stderr, "bench_soak: %s: [--seconds S] [--engine kinetic|dsmc|ed|ts|dem]...\n", argv[i]);
      return 2;
    }
  }
  const std::vector<EngineSoak> engines{
      {"kinetic", {{"|M1 - 1|", 1e-12}}, kinetic_run},
      {"dsmc", {{"integer mass off (0/1)", 0}, {"|M1 + leaked - 1|", 1e-12}}, dsmc_run},
      {"ed", {{"|P - P0| / sum|v|", 1e-10}, {"largest overlap", EventDrivenAggregation::overlap_tolerance}}, ed_run},
      {"ts", {{"|P - P0| / sum|v|", 1e-10}, {"largest 1 - |dx|/2R", TimeSteppingAggregation::same_cluster_tolerance}}, ts_run},
      {"dem", {{"|E - E0| / E0", 1e-3}, {"|P - P0| / sum m|v|", 1e-10}}, dem_run},
  };
  const bench::Figures figures("soak", argc, argv);
  bench::print_load();
  std::printf("# bench_soak --seconds %g: each engine run again and again for %g s of wall time\n", seconds, seconds);
  bool all_hold = true;
  for (const auto& e : engines) {
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), e.name) == wanted.end()) continue;
    Soak soak(e.invariants);
    const auto started = Clock::now();
    const std::clock_t cpu0 = std::clock();
    while (std::chrono::duration<double>(Clock::now() - started).count() < seconds) {
      e.run(soak);
      ++soak.runs;
      soak.rss.push_back(rss_mib());
    }
    const double wall = std::chrono::duration<double>(Clock::now() - started).count();
    const double cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
    const double first = soak.rss.front(), largest = *std::max_element(soak.rss.begin(), soak.rss.end());
    const bool memory_holds = soak.runs < 2 || largest - first <= 0.1 * first + 16;
    std::printf("%-8s %zu runs, %zu checks in %.0f s wall (%.0f s CPU); RSS after run 1 %.1f MiB, largest later %.1f MiB, last %.1f MiB: %s\n",
                e.name, soak.runs, soak.checks, wall, cpu, first, largest, soak.rss.back(),
                memory_holds ? (soak.runs < 2 ? "one run only: growth not measured" : "no growth beyond the bound") : "GROWS");
    all_hold = all_hold && memory_holds && soak.runs >= 2;
    figures.add(e.name, "runs", double(soak.runs), "1");
    figures.add(e.name, "rss_growth", largest - first, "MiB");
    for (const auto& i : soak.invariants) {
      std::printf("         %-24s worst %.3g (bound %.3g) at %s: %s\n", i.name.c_str(), i.worst, i.bound,
                  i.where.empty() ? "-" : i.where.c_str(), i.holds() ? "holds" : "VIOLATED");
      all_hold = all_hold && i.holds();
      figures.add(e.name, i.name, i.worst, "1");
    }
    std::fflush(stdout);
  }
  return all_hold ? 0 : 1;
}
