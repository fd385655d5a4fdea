// TS cost study [Degond2024, Sec. 4.1] against our ED on the same starts, in the same run: 2-D discs on a
// square lattice at volume fraction ν, unit speed in uniform directions, reflecting walls (the published
// setup; R = 1/2 here, lengths scale), run to one cluster by TS and then by ED (interleaved per N).
//   bench_ts_cost cost DT_FACTOR NU N1 [N2 ...]      one line per N, then the cost exponents (log-log fits)
//   bench_ts_cost threads DT_FACTOR NU N REPEATS     cluster_threads 1 and 2 alternated, REPEATS times each
//   bench_ts_cost ts DT_FACTOR NU N1 [N2 ...]        as cost, TS only (ED columns 0): for A/B runs of TS builds
//   ... --threads K                                  (cost, ts) TS on K cluster threads; wall seconds recorded too
// Per N: TS seconds, steps, substeps, merges, minimisation iterations per merge, free spheres per
// minimisation, merges found after a minimisation (secondary), ED seconds and events, TS/ED, and the
// flights within a safe time, which skip contact detection (quiet), and the spheres re-checked after
// contact-time merges (recheck).
// Iterations per merge and free spheres per minimisation flat in N mean the minimisation work follows the
// new contacts, not N [Degond2024, Sec. 3.3]; the rest of a step (flight and contact detection) is O(N)
// per flight (detection and the cell update skipped in quiet flights).
#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "analysis/least_squares.hpp"
#include "bench/ed_common.hpp"
#include "bench/figures.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

using namespace aggkit;

namespace {

// Processor time of this process: on a shared machine a single-threaded run's CPU seconds are steadier than
// its wall seconds (the threads mode, which needs wall time, states the load instead).
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

constexpr std::uint64_t max_steps = 200000;

struct TsRun {
  double seconds, cpu;
  TsCounters counters;
  std::size_t clusters;
};

TsRun run_ts(std::size_t n, double nu, double dt_factor, std::size_t threads, std::uint64_t seed = 1) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(2, n, radius, nu);
  const Box box{2, {side, side, 0.0}, Boundary::reflecting};
  TsSettings settings;
  settings.dt_factor = dt_factor;
  settings.threads = threads;
  // A/B switch for the near re-check (same run either way): AGGKIT_TS_NEAR_RECHECK=0 re-checks every moved sphere.
  if (const char* near = std::getenv("AGGKIT_TS_NEAR_RECHECK")) settings.near_recheck = std::strcmp(near, "0") != 0;
  TimeSteppingAggregation ts(box, radius, lattice_positions(box, n, radius),
                             initial_velocities(2, n, VelocityLaw::fixed_speed, 1.0, seed), settings);
  const auto start = std::chrono::steady_clock::now();
  const double cpu0 = cpu_seconds();
  // To one cluster, or until no cluster moves relative to another (a cluster as wide as the box is held
  // at rest along that axis, so the last clusters can end up never meeting), or a step cap.
  while (ts.clusters() > 1 && !ts.at_rest() && ts.counters().steps < max_steps)
    ts.advance(ts.time() + 64 * ts.time_step(), 1);
  if (ts.clusters() > 1)
    std::printf("# N %zu: stopped with %zu clusters after %llu steps (%s)\n", n, ts.clusters(),
                (unsigned long long)ts.counters().steps, ts.at_rest() ? "at rest" : "step cap");
  return {bench::seconds_since(start), cpu_seconds() - cpu0, ts.counters(), ts.clusters()};
}

double exponent(const std::vector<double>& n, const std::vector<double>& t, double& error) {
  std::vector<double> x, y;
  for (std::size_t k = 0; k < n.size(); ++k) {
    x.push_back(std::log(n[k]));
    y.push_back(std::log(t[k]));
  }
  const LineFit f = fit_line(x, y);
  error = f.slope_error;
  return f.slope;
}

}  // namespace

int main(int argc, char** argv) {
  const bool ts_only = argc >= 2 && std::strcmp(argv[1], "ts") == 0;
  // `--threads K` (cost and ts modes): cluster threads of the TS runs (default 1). With K > 1 the case names
  // carry threads=K and the wall seconds are recorded too (CPU seconds then count every thread).
  std::size_t cluster_threads = 1;
  std::vector<char*> command(argv, argv + argc);  // as given, for the figures' command column
  for (int k = 1; k + 1 < argc; ++k)
    if (std::strcmp(argv[k], "--threads") == 0) {
      cluster_threads = std::size_t(std::max(1, std::atoi(argv[k + 1])));
      for (int m = k; m + 2 < argc; ++m) argv[m] = argv[m + 2];
      argc -= 2;
      break;
    }
  if (argc < 5 || (std::strcmp(argv[1], "cost") != 0 && std::strcmp(argv[1], "threads") != 0 && !ts_only)) {
    std::fprintf(stderr, "usage: %s cost|ts DT_FACTOR NU N1 [N2 ...] [--threads K] | threads DT_FACTOR NU N REPEATS\n", argv[0]);
    return 2;
  }
  const double dt_factor = std::atof(argv[2]), nu = std::atof(argv[3]);
  const bench::Figures figures("ts_cost", int(command.size()), command.data());
  const std::string setup = "nu=" + bench::Figures::text(nu) + " dt_factor=" + bench::Figures::text(dt_factor) +
                            (cluster_threads > 1 ? " threads=" + std::to_string(cluster_threads) : "");
  bench::print_load();
  if (std::strcmp(argv[1], "threads") == 0) {
    const auto n = std::size_t(std::atof(argv[4]));
    const int repeats = argc > 5 ? std::atoi(argv[5]) : 3;
    double one = 0, two = 0;
    for (int r = 0; r < repeats; ++r) {
      const TsRun a = run_ts(n, nu, dt_factor, 1), b = run_ts(n, nu, dt_factor, 2);
      std::printf("N %zu nu %g dt_factor %g: 1 thread %.3f s, 2 threads %.3f s (same steps: %s)\n", n, nu, dt_factor, a.seconds,
                  b.seconds, a.counters.steps == b.counters.steps ? "yes" : "NO");
      one += a.seconds;
      two += b.seconds;
    }
    std::printf("speed-up with 2 threads: %.2f\n", one / two);
    figures.add(setup + " N=" + bench::Figures::text(double(n)), "speedup_2_threads", one / two, "1");
    bench::print_load();
    return 0;
  }
  std::printf("# 2-D reflecting, square lattice, unit speed, nu %g, TS dt_factor %g, to one cluster; TS then ED per N\n", nu,
              dt_factor);
  std::printf("%9s %9s %9s %8s %9s %8s %9s %9s %9s %9s %9s %10s %9s %9s %10s %9s %10s\n", "N", "ts_cpu_s", "ts_wall_s", "steps",
              "substeps", "merges", "iter/mrg", "free/min", "secondary", "ed_cpu_s", "ed_wall_s", "ed_events", "ts/ed_cpu",
              "quiet", "recheck", "local", "examined/N");
  std::vector<double> ns, ts_times, ed_times;
  for (int k = 4; k < argc; ++k) {
    const auto n = std::size_t(std::atof(argv[k]));
    const TsRun ts = run_ts(n, nu, dt_factor, cluster_threads);
    auto ed = bench::make_ed(2, ts_only ? 2 : n, nu, Boundary::reflecting, true, 1);
    const auto start = std::chrono::steady_clock::now();
    const double cpu0 = cpu_seconds();
    if (!ts_only) ed.advance(1e30, 1);
    const double ed_seconds = bench::seconds_since(start), ed_cpu = cpu_seconds() - cpu0;
    const TsCounters& c = ts.counters;
    std::printf("%9zu %9.3f %9.3f %8llu %9llu %8llu %9.1f %9.1f %9llu %9.3f %9.3f %10llu %9.2f %9llu %10llu %9llu %10.1f\n", n, ts.cpu, ts.seconds,
                (unsigned long long)c.steps, (unsigned long long)c.substeps, (unsigned long long)c.merges,
                double(c.minimisation_iterations) / double(std::max<std::uint64_t>(c.merges, 1)),
                double(c.free_spheres) / double(std::max<std::uint64_t>(c.minimisations, 1)),
                (unsigned long long)c.secondary_merges, ed_cpu, ed_seconds, (unsigned long long)ed.counters().events(),
                ts_only ? 0.0 : ts.cpu / ed_cpu, (unsigned long long)c.quiet_flights, (unsigned long long)c.rechecked_spheres,
                (unsigned long long)c.local_passes, double(c.examined_spheres) / double(n));
    std::fflush(stdout);
    if (ts_only) {
      figures.add(setup + " N=" + bench::Figures::text(double(n)), "ts_cpu_seconds", ts.cpu, "s");
      if (cluster_threads > 1) figures.add(setup + " N=" + bench::Figures::text(double(n)), "ts_wall_seconds", ts.seconds, "s");
      ns.push_back(double(n));
      ts_times.push_back(std::max(ts.cpu, 1e-3));
      continue;
    }
    const std::string at = setup + " N=" + bench::Figures::text(double(n));
    figures.add(at, "ts_cpu_seconds", ts.cpu, "s");
    figures.add(at, "ed_cpu_seconds", ed_cpu, "s");
    figures.add(at, "ts_over_ed_cpu", ts.cpu / ed_cpu, "1");
    ns.push_back(double(n));
    ts_times.push_back(std::max(ts.cpu, 1e-3));  // clock() resolution
    ed_times.push_back(std::max(ed_cpu, 1e-3));
  }
  if (ts_only && ns.size() >= 3) {
    double e_ts = 0;
    const double x_ts = exponent(ns, ts_times, e_ts);
    std::printf("# cost exponent (CPU seconds, least squares in log-log over all N): TS %.3f ± %.3f\n", x_ts, e_ts);
  } else if (ns.size() >= 3) {
    double e_ts = 0, e_ed = 0;
    const double x_ts = exponent(ns, ts_times, e_ts), x_ed = exponent(ns, ed_times, e_ed);
    std::printf("# cost exponent (CPU seconds, least squares in log-log over all N): TS %.3f ± %.3f, ED %.3f ± %.3f\n", x_ts, e_ts, x_ed, e_ed);
    figures.add(setup, "ts_cost_exponent", x_ts, "1");
    figures.add(setup, "ed_cost_exponent", x_ed, "1");
  }
  bench::print_load();
}
