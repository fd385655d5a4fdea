#pragma once
// Shared set-up of the ED benchmarks: N particles of radius 1/2 on a lattice at volume fraction ν,
// velocities of unit speed with uniform directions (seeded), in a square/cubic box.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "particle/common/initial_state.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

namespace aggkit::bench {

inline EventDrivenAggregation make_ed(int dimension, std::size_t count, double nu, Boundary boundary, bool sticking,
                                      std::uint64_t seed = 1, VelocityLaw law = VelocityLaw::fixed_speed) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(dimension, count, radius, nu);
  const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, boundary};
  const auto x = lattice_positions(box, count, radius);
  const auto v = initial_velocities(dimension, count, law, 1.0, seed);
  return EventDrivenAggregation(box, radius, x, v, sticking);
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline void print_load() {
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    char line[128] = {0};
    if (std::fgets(line, sizeof line, f)) std::printf("# load average: %s", line);
    std::fclose(f);
  }
}

}  // namespace aggkit::bench
