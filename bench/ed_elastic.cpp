// ED elastic mode (the thermalisation stage, sticking off): collisions per second, counting collisions only,
// for hard discs/spheres at volume fraction ν. Reference (issue 5): a general-purpose event-driven MD code
// reaches 2.2e4 collisions/s (2-D, ν = 0.01, N = 1e6) and 5e4 (3-D, ν = 0.25, N = 1e6) on one core.
//   bench_ed_elastic DIM NU COLLISIONS_PER_PARTICLE N1 [N2 ...]   (periodic box, unit speeds)
// The timed part starts after one collision per particle (the lattice start is not representative).
#include <cstdio>
#include <cstdlib>

#include "bench/ed_common.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s DIM NU COLLISIONS_PER_PARTICLE N1 [N2 ...]\n", argv[0]);
    return 2;
  }
  const int dimension = std::atoi(argv[1]);
  const double nu = std::atof(argv[2]);
  const double per_particle = std::atof(argv[3]);
  bench::print_load();
  std::printf("# elastic, dim %d periodic nu %g, %g collisions per particle timed\n", dimension, nu, per_particle);
  std::printf("%10s %8s %12s %12s %12s %14s %12s\n", "N", "setup_s", "run_s", "collisions", "crossings",
              "collisions/s", "energy_drift");
  for (int k = 4; k < argc; ++k) {
    const auto n = std::size_t(std::atof(argv[k]));
    auto start = std::chrono::steady_clock::now();
    auto ed = bench::make_ed(dimension, n, nu, Boundary::periodic, false);
    const double e0 = ed.kinetic_energy();
    // Warm-up: about one collision per particle (mean free time at unit speed is ~ mean free path).
    while (ed.counters().elastic_collisions < n / 2 && ed.step()) {
    }
    const double setup = bench::seconds_since(start);
    const auto c0 = ed.counters();
    const auto target = c0.elastic_collisions + std::uint64_t(per_particle * double(n) / 2);
    start = std::chrono::steady_clock::now();
    while (ed.counters().elastic_collisions < target && ed.step()) {
    }
    const double run = bench::seconds_since(start);
    const auto& c = ed.counters();
    const double collisions = double(c.elastic_collisions - c0.elastic_collisions);
    std::printf("%10zu %8.2f %12.2f %12.0f %12llu %14.3g %12.2e\n", n, setup, run, collisions,
                (unsigned long long)(c.cell_crossings - c0.cell_crossings), collisions / run,
                std::abs(ed.kinetic_energy() - e0) / e0);
    std::fflush(stdout);
  }
  bench::print_load();
}
