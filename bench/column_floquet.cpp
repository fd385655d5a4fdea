// The largest Floquet multiplier of a cached step of a scan's cycle column, from the return map
// (solvers/cycle_return_map.hpp): what it costs (CPU seconds, returns) and what it finds.
//   bench_column_floquet a lambda state_file period m0_min m0_max spread atol atol_floor atol_mass [max_steps]
// state_file: DIR/points/cycle_column_a*_lambda*_N*_state.txt of the shipped scan (graded K = 64, r = 1.05,
// N = 2^40); period, m0_min, m0_max, spread, atol, atol_floor and atol_mass: the step's record
// (cycle_column_*.csv). PERTURBATION=, FLOOR= and RESOLVED= (resolved_factor) in the environment set those options.
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <vector>

#include "bench/scan_model.hpp"
#include "solvers/cycle_return_map.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  if (argc < 11) {
    std::fprintf(stderr, "usage: bench_column_floquet a lambda state_file period m0_min m0_max spread atol atol_floor atol_mass [max_steps]\n");
    return 2;
  }
  const auto [model, state] = bench::column_step(argv[1], argv[2], argv[3]);
  const CycleReference reference{std::atof(argv[4]), std::atof(argv[5]), std::atof(argv[6]), std::atof(argv[7])};
  ReturnMapOptions options;
  options.tolerance = {.atol = std::atof(argv[8]), .atol_floor = std::atof(argv[9]), .atol_mass = std::atof(argv[10])};
  options.max_steps = argc > 11 ? std::atol(argv[11]) : 120000;
  if (const char* p = std::getenv("PERTURBATION")) options.perturbation = std::atof(p);
  if (const char* f = std::getenv("FLOOR")) options.floor = std::atof(f);
  if (const char* r = std::getenv("RESOLVED")) options.resolved_factor = std::atof(r);
  const std::clock_t started = std::clock();
  const ReturnMapMultiplier m = return_map_multiplier(model, state, reference, options);
  std::printf("a %s lambda %s: |mu| %.4g +- %.2g%s, %s; cpu %.1f s\n  deviations:", argv[1], argv[2], m.multiplier,
              m.multiplier_error, m.bounded ? " (bound)" : "", m.note.c_str(), double(std::clock() - started) / CLOCKS_PER_SEC);
  for (double d : m.deviations) std::printf(" %.3g", d);
  std::printf("\n");
  return 0;
}
