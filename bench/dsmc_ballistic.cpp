// DSMC accuracy and speed for the ballistic kernel with shattering, λ = 0.01, monodisperse ([Kalinov2022,
// Tables 2 and 4]): relative RMS error per run (the paper's "std over runs") of M0, M2, M3 at t = 1, 10, 100
// against CVODE (N = 5000, rtol 1e-8; within 1e-7 of a rtol 1e-12 reference, bench/results/log/cvode-work-precision.md, CVODE
// work-precision), and run time / accepted events per second of one run to t = 100.
//   bench_dsmc_ballistic PARTICLES RUNS [method ar|fast] [bucket] [halving 1|0]
// (halving 0, the default: population control only doubles, as in [Kalinov2022]; halving 1: the case name
// says halving=1)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "particle/dsmc/simulation.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {
// CPU time of this thread: on a shared machine it is far less sensitive to the load than the wall time.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t particles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 100000;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 4;
  dsmc::Options options;
  options.particles = particles;
  if (argc > 3) options.method = dsmc::method_from_name(argv[3]);
  if (argc > 4) options.bucket = std::strtoull(argv[4], nullptr, 10);
  if (argc > 5) options.population_halving = std::atoi(argv[5]) != 0;
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(0.01);
  model.size = 5000;
  model.initial = monodisperse(model.size);
  const std::vector<double> times{1.0, 10.0, 100.0}, orders{0.0, 2.0, 3.0};
  std::vector<std::vector<double>> reference;
  IntegratorOptions tight;
  tight.rtol = 1e-8;
  integrate(model, times, tight, [&](double, std::span<const double> n, double) {
    reference.push_back({moment(n, 0.0), moment(n, 2.0), moment(n, 3.0)});
  });
  std::vector<std::vector<double>> squares(3, std::vector<double>(3, 0.0)), sums = squares;
  double wall_total = 0.0, cpu_total = 0.0, events_total = 0.0;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    dsmc::Simulation simulation(model, options, dsmc::run_seed(1, r), 100.0);
    for (std::size_t i = 0; i < times.size(); ++i) {
      simulation.advance_to(times[i]);
      const auto s = simulation.snapshot();
      for (std::size_t p = 0; p < orders.size(); ++p) {
        const double e = s.moment(orders[p]) / reference[i][p] - 1.0;
        squares[i][p] += e * e;
        sums[i][p] += e;
      }
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    wall_total += wall;
    cpu_total += cpu_seconds() - cpu_start;
    events_total += double(simulation.statistics().accepted());
    std::printf("run %d: %.2f s, %llu accepted of %llu trials, %llu doublings, %llu halvings, %llu particles at t = 100\n",
                r, wall, (unsigned long long)simulation.statistics().accepted(),
                (unsigned long long)simulation.statistics().trials, (unsigned long long)simulation.statistics().doublings,
                (unsigned long long)simulation.statistics().halvings, (unsigned long long)simulation.snapshot().particles);
  }
  std::printf("| %s | %llu | %d |", dsmc::to_string(options.method).c_str(), (unsigned long long)particles, runs);
  for (std::size_t i = 0; i < 3; ++i)
    std::printf(" %.2g, %.2g, %.2g %% |", 100 * std::sqrt(squares[i][0] / runs), 100 * std::sqrt(squares[i][1] / runs),
                100 * std::sqrt(squares[i][2] / runs));
  std::printf(" %.2f s | %.3g |\n", wall_total / runs, events_total / wall_total);
  std::printf("cpu time per run %.2f s (wall %.2f s), accepted events per cpu second %.3g (%.1f ns per event)\n",
              cpu_total / runs, wall_total / runs, events_total / cpu_total, 1e9 * cpu_total / events_total);
  const aggkit::bench::Figures figures("dsmc_ballistic", argc, argv);
  const std::string case_name = "particles=" + std::to_string(particles) + " method=" + dsmc::to_string(options.method) +
                                (options.population_halving ? " halving=1" : "");
  figures.add(case_name, "wall_seconds", wall_total / runs, "s");
  figures.add(case_name, "events_per_second", events_total / wall_total, "1/s");
  figures.add(case_name, "cpu_seconds", cpu_total / runs, "s");
  figures.add(case_name, "cpu_ns_per_event", 1e9 * cpu_total / events_total, "ns");
  const char* moment_names[] = {"M0", "M2", "M3"};
  const char* time_names[] = {"t1", "t10", "t100"};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t p = 0; p < 3; ++p)
      figures.add(case_name, std::string("rms_error_") + moment_names[p] + "_" + time_names[i],
                  std::sqrt(squares[i][p] / runs), "1");
  std::printf("mean relative deviation (bias + noise/sqrt(runs)) at t = 100: %.2g, %.2g, %.2g %%\n",
              100 * sums[2][0] / runs, 100 * sums[2][1] / runs, 100 * sums[2][2] / runs);
  return 0;
}
