// ED aggregation throughput: events per second and time to one cluster as functions of N and the
// volume fraction ν, 2-D or 3-D, periodic or reflecting.
//   bench_ed_throughput DIM BOUNDARY NU N1 [N2 ...]    e.g. bench_ed_throughput 2 periodic 0.01 1e4 1e5 1e6
// Prints one line per N: set-up seconds, seconds to one cluster, events (merges, broad-phase crossings of
// cluster boxes, pair checks, walls), stale events skipped, events/s, and the cost exponent between
// consecutive N (log t2/t1 / log N2/N1).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "bench/ed_common.hpp"
#include "bench/figures.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s DIM periodic|reflecting NU N1 [N2 ...]\n", argv[0]);
    return 2;
  }
  const int dimension = std::atoi(argv[1]);
  const Boundary boundary = boundary_from_name(argv[2]);
  const double nu = std::atof(argv[3]);
  bench::print_load();
  std::printf("# dim %d %s nu %g, unit speed uniform directions, run to one cluster\n", dimension, argv[2], nu);
  std::printf("%10s %8s %10s %12s %12s %12s %12s %10s %12s %12s %8s\n", "N", "setup_s", "run_s", "events", "merges",
              "crossings", "pair_checks", "walls", "stale", "events/s", "exponent");
  const bench::Figures figures("ed_throughput", argc, argv);
  double previous_n = 0, previous_t = 0;
  for (int k = 4; k < argc; ++k) {
    const auto n = std::size_t(std::atof(argv[k]));
    auto start = std::chrono::steady_clock::now();
    auto ed = bench::make_ed(dimension, n, nu, boundary, true);
    const double setup = bench::seconds_since(start);
    start = std::chrono::steady_clock::now();
    // Progress on stderr about once a minute: clusters left, events so far (a long 3-D run shows how far it got).
    auto reported = start;
    ed.advance(1e30, 1, [&] {
      if (bench::seconds_since(reported) < 60) return;
      reported = std::chrono::steady_clock::now();
      std::fprintf(stderr, "# N %zu: %.0f s, %zu clusters left, %llu events\n", n, bench::seconds_since(start), ed.clusters(),
                   (unsigned long long)ed.counters().events());
    });
    const double run = bench::seconds_since(start);
    const auto& c = ed.counters();
    const double exponent = previous_n > 0 ? std::log(run / previous_t) / std::log(double(n) / previous_n) : NAN;
    std::printf("%10zu %8.2f %10.2f %12llu %12llu %12llu %12llu %10llu %12llu %12.3g %8.2f\n", n, setup, run,
                (unsigned long long)c.events(), (unsigned long long)c.merges, (unsigned long long)c.cell_crossings,
                (unsigned long long)c.pair_checks, (unsigned long long)c.wall_contacts,
                (unsigned long long)c.stale_events, double(c.events()) / run, exponent);
    std::fflush(stdout);
    const std::string case_name = "dim=" + std::to_string(dimension) + " " + argv[2] + " nu=" + bench::Figures::text(nu) +
                                  " N=" + bench::Figures::text(double(n));
    figures.add(case_name, "seconds_to_one_cluster", run, "s");
    figures.add(case_name, "events_per_second", double(c.events()) / run, "1/s");
    if (previous_n > 0) figures.add(case_name, "cost_exponent", exponent, "1");
    previous_n = double(n);
    previous_t = run;
  }
  bench::print_load();
}
