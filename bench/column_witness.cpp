// Which witness of the return map sees the largest Floquet multiplier of a cached column step: the period
// changes that solvers/cycle_return_map.hpp fits, against the state's own changes at the section. From the
// step's state, perturbed as the return map perturbs it (mass_keeping_perturbation, relative size `epsilon`; 0:
// unperturbed, the integration's noise floor), `returns` returns to the section M0 = (m0_min + m0_max) / 2 at the
// step's tolerances (rtol 1e-6), each printed with
//   dT/T        the change of the period from the return before, relative (the return map's deviations);
//   L1 mass     Σ x_i |y_i − y_i'| / Σ x_i |y_i| between successive section states y' and y;
//   max rel     max_i |y_i − y_i'| / (|y_i| + 1e-8 max |y|), and the class where it is largest.
// A dominant mode that does not move the period would show as a state deviation falling more slowly than dT/T.
//   bench_column_witness a lambda state_file period m0_min m0_max atol atol_floor atol_mass epsilon returns
// state_file and the numbers: a cached step of the shipped scan (graded K = 64, r = 1.05, N = 2^40), as for
// bench_column_floquet.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "bench/scan_model.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/cycle_return_map.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/poincare_section.hpp"

using namespace aggkit;

namespace {

struct Enough {};

void print_return(std::size_t j, const std::vector<double>& times, const std::vector<double>& y, const std::vector<double>& before,
                  const std::vector<double>& sizes, double period) {
  double largest = 0.0;
  for (double v : y) largest = std::max(largest, std::abs(v));
  double max_rel = 0.0, moved = 0.0, mass = 0.0;
  std::size_t where = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double r = std::abs(y[i] - before[i]) / (std::abs(y[i]) + 1e-8 * largest);
    if (r > max_rel) {
      max_rel = r;
      where = i;
    }
    moved += sizes[i] * std::abs(y[i] - before[i]);
    mass += sizes[i] * std::abs(y[i]);
  }
  const std::size_t c = times.size();
  const double change = c >= 3 ? std::abs((times[c - 1] - times[c - 2]) - (times[c - 2] - times[c - 3])) / period : NAN;
  std::printf("return %zu  t %.6g  dT/T %.3e  L1 mass %.3e  max rel %.3e (class %zu)\n", j, times.back(), change, moved / mass,
              max_rel, where);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 12) {
    std::fprintf(stderr, "usage: bench_column_witness a lambda state_file period m0_min m0_max atol atol_floor atol_mass epsilon returns\n");
    return 2;
  }
  const auto [model, state] = bench::column_step(argv[1], argv[2], argv[3]);
  const double period = std::atof(argv[4]), level = 0.5 * (std::atof(argv[5]) + std::atof(argv[6]));
  const RunTolerance tolerance{std::atof(argv[7]), std::atof(argv[8]), std::atof(argv[9])};
  const double epsilon = std::atof(argv[10]);
  const int returns = std::atoi(argv[11]);
  const std::vector<double> sizes = make_discretisation(model)->sizes();
  IntegratorRestart restart;
  restart.densities = epsilon > 0.0 ? mass_keeping_perturbation(state, sizes, epsilon) : state;
  IntegratorOptions options = cycle_run_options(1e-6, 400000, tolerance);
  UpwardCrossings section(level, true);
  std::vector<double> times;
  std::vector<double> before;
  options.on_step = [&](double t, std::span<const double> n) {
    if (!section.add(t, n)) return;
    times.push_back(section.time());
    if (!before.empty()) print_return(times.size() - 1, times, section.state(), before, sizes, period);
    before = section.state();
    if (int(times.size()) > returns) throw Enough{};
  };
  const std::clock_t started = std::clock();
  try {
    integrate(model, std::vector<double>{(returns + 3.0) * period}, options, [](double, std::span<const double>, double) {}, &restart);
  } catch (const Enough&) {
  }
  std::printf("cpu %.1f s\n", double(std::clock() - started) / CLOCKS_PER_SEC);
  return 0;
}
