// One step of a scan's cycle column, rerun from the state a cached step ended in, with the integrator's
// method, rtol and atol floor chosen: what a column step costs (CPU seconds, CVODE steps, right-hand sides,
// linear iterations, failures) and what it finds (the period from the upward crossings of M0's mid-range over
// the run's second half, M0's range, the mass change, and whether the periods settled: analysis/crossing_periods.hpp).
//   bench_column_step a lambda state_file period periods method rtol atol_floor [max_steps]
// state_file: DIR/points/cycle_column_a*_lambda*_N*_state.txt of the shipped scan (graded K = 64, r = 1.05,
// N = 2^40); period: the predicted period; method: bdf-gmres, bdf-dense, ... ATOL= and ATOL_MASS= in the
// environment set the integrator's atol and atol_mass, STALD=1 CVODE's stability limit detection (default off,
// as in the scan's columns), PROJECT=0 no mass projection (the scan's columns project neither steps nor outputs at
// their atol); STEPS_OUT=file writes t, M0 and n_1 at every internal
// step. With TRACE=m, every m-th output prints t, M0, n_1, the
// mass, the leaked mass, the most negative density (its class and pivot) and the largest, and the last class
// that is not empty.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/crossing_periods.hpp"
#include "bench/scan_model.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {

// The run's second half: M0 at each output.
struct Tail {
  std::vector<double> t, m0;
  std::vector<double> step_t, step_m0;  // M0 at the internal steps of the second half
};

// Its crossings, periods, peaks and settling verdict.
void report(const Tail& tail, double start_mass, double end_mass) {
  const CrossingPeriods c = crossing_periods(tail.t, tail.m0);
  const CycleSettlingVerdict v = cycle_settling(c, tail.m0);
  const std::vector<double>& m0 = tail.m0;
  // The integrator holds Σ x n + L on the unit start's mass: the change against it, as the column's guard.
  std::printf("  M0 %.6g .. %.6g, start mass %.8g, mass change %.3g, crossings %zu, periods:", c.lowest, c.highest, start_mass,
              end_mass - 1, c.crossings.size());
  for (double p : c.periods) std::printf(" %.7g", p);
  std::printf("\n  peaks (largest output of each period, its larger neighbour / it, and the parabola's vertex through them):");
  for (std::size_t i = 1; i < c.after.size(); ++i) {
    const auto top = std::max_element(m0.begin() + long(c.after[i - 1]), m0.begin() + long(c.after[i]));
    std::printf(" %.6g (%.2f, %.6g)", *top, std::max(*(top - 1), *(top + 1)) / *top, peak_between({}, m0, c.after[i - 1], c.after[i]));
  }
  std::printf("\n  troughs and means over each period:");
  for (std::size_t i = 1; i < c.after.size(); ++i) {
    const auto low = std::min_element(m0.begin() + long(c.after[i - 1]), m0.begin() + long(c.after[i]));
    double sum = 0;
    for (std::size_t k = c.after[i - 1]; k < c.after[i]; ++k) sum += 0.5 * (m0[k] + m0[k + 1]) * (tail.t[k + 1] - tail.t[k]);
    std::printf(" %.6g (%.6g)", *low, sum / (tail.t[c.after[i]] - tail.t[c.after[i - 1]]));
  }
  std::printf("\n  %s: period %.7g, spread %.3g, contraction %.3g a period\n", to_string(v.settling).c_str(), v.period, v.spread,
              v.contraction);
  // The same over the internal steps, as the scan's columns read it.
  const std::vector<double>&t = tail.step_t, &x = tail.step_m0;
  const CrossingPeriods fc = crossing_periods(t, x);
  const CycleSettlingVerdict fv = cycle_settling(fc, t, x);
  std::printf("  with the %zu steps: M0 %.6g .. %.6g, troughs:", tail.step_t.size(), fc.lowest, fc.highest);
  for (std::size_t i = 1; i < fc.after.size(); ++i)
    std::printf(" %.6g", *std::min_element(x.begin() + long(fc.after[i - 1]), x.begin() + long(fc.after[i])));
  std::printf("\n  %s: period %.7g, spread %.3g\n", to_string(fv.settling).c_str(), fv.period, fv.spread);
}

// The integrator's options from the command line (method, rtol, floor, max_steps) and ATOL=, ATOL_MASS=, STALD=
// (CVODE's stability limit detection, 1 or 0; the scan's column runs have it off), PROJECT= (the mass projection,
// 1 or 0; below atol 1e-10 it projects the outputs only).
IntegratorOptions options_from(int argc, char** argv) {
  IntegratorOptions options;
  options.method = integrator_method_from_name(argv[6]);
  options.rtol = std::atof(argv[7]);
  options.atol_floor = std::atof(argv[8]);
  options.max_steps = argc > 9 ? std::atol(argv[9]) : 40000;
  options.stability_limit_detection = false;
  if (const char* stald = std::getenv("STALD")) options.stability_limit_detection = std::atoi(stald) != 0;
  if (const char* atol = std::getenv("ATOL")) options.atol = std::atof(atol);
  if (const char* mass = std::getenv("ATOL_MASS")) options.atol_mass = std::atof(mass);
  if (const char* project = std::getenv("PROJECT")) options.project_mass = std::atoi(project) != 0;
  return options;
}

// One TRACE line: t, M0, n_1, the mass, the leaked mass, the most negative density (its class and pivot), the
// largest, and the last class that is not empty.
void trace_line(double t, std::span<const double> n, double leaked, const std::vector<double>& pivots) {
  double s = 0, m = 0;
  for (std::size_t k = 0; k < n.size(); ++k) s += n[k], m += pivots[k] * n[k];
  const auto lowest = std::min_element(n.begin(), n.end());
  const auto largest = std::max_element(n.begin(), n.end());
  std::size_t last = n.size();
  while (last > 0 && std::abs(n[last - 1]) < 1e-30) --last;
  std::printf("  t %.6g M0 %.4g n1 %.4g mass %.8g leaked %.3g lowest %.3g at %zu (%.3g; %.3g at %zu), last %zu\n", t, s, n[0], m,
              leaked, *lowest, std::size_t(lowest - n.begin()), pivots[std::size_t(lowest - n.begin())], *largest,
              std::size_t(largest - n.begin()), last);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 9) {
    std::fprintf(stderr, "usage: bench_column_step a lambda state_file period periods method rtol atol_floor [max_steps]\n");
    return 2;
  }
  const double a = std::atof(argv[1]), lambda = std::atof(argv[2]);
  const double period = std::atof(argv[4]), periods = std::atof(argv[5]);
  IntegratorOptions options = options_from(argc, argv);
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  AggregationModel model = bench::scan_model(grid, a);
  model.lambda = ShatteringRate::constant(lambda);
  IntegratorRestart restart;
  std::ifstream in(argv[3]);
  for (double v; in >> v;) restart.densities.push_back(std::max(v, 0.0));
  if (restart.densities.size() != model.unknowns()) {
    std::fprintf(stderr, "state has %zu values, the model %zu\n", restart.densities.size(), model.unknowns());
    return 2;
  }
  const std::vector<double> pivots = model.pivots();
  const auto mass = [&](const std::vector<double>& n) {
    double m = 0;
    for (std::size_t k = 0; k < n.size(); ++k) m += pivots[k] * n[k];
    return m;
  };
  const double start_mass = mass(restart.densities);
  const double end = periods * period, spacing = period / (std::getenv("OUTPUTS") ? std::atof(std::getenv("OUTPUTS")) : 50.0);
  std::vector<double> times;
  for (double t = spacing; t <= end * (1 + 1e-12); t += spacing) times.push_back(t);
  Tail tail;
  std::vector<double> last;
  const long trace = std::getenv("TRACE") ? std::atol(std::getenv("TRACE")) : 0;
  long outputs = 0;
  const std::clock_t c0 = std::clock();
  std::FILE* steps_out = std::getenv("STEPS_OUT") ? std::fopen(std::getenv("STEPS_OUT"), "w") : nullptr;
  options.on_step = [&](double t, std::span<const double> n) {
    if (steps_out) {
      double s = 0;
      for (double v : n) s += v;
      std::fprintf(steps_out, "%.17g %.17g %.17g\n", t, s, n[0]);
    }
    if (t < 0.5 * end || t > end) return;
    double s = 0;
    for (double v : n) s += v;
    tail.step_t.push_back(t);
    tail.step_m0.push_back(s);
  };
  IntegratorStatistics stats;
  std::string failure;
  try {
    stats = integrate(model, times, options, [&](double t, std::span<const double> n, double leaked) {
      last.assign(n.begin(), n.end());
      if (trace > 0 && outputs++ % trace == 0) trace_line(t, n, leaked, pivots);
      if (t < 0.5 * end) return;
      double s = 0;
      for (double v : n) s += v;
      tail.t.push_back(t);
      tail.m0.push_back(s);
    }, &restart);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  if (steps_out) std::fclose(steps_out);
  std::printf("a %g lambda %g method %s rtol %g atol %g floor %g atol_mass %g: cpu %.1f s\n", a, lambda, argv[6], options.rtol,
              options.atol, options.atol_floor, options.atol_mass, cpu);
  if (!failure.empty()) {
    std::printf("  failed: %s\n", failure.c_str());
    return 1;
  }
  std::printf("  steps %ld rhs %ld lin %ld jv %ld jac %ld psetup %ld etf %ld ncf %ld lcf %ld\n", stats.steps, stats.rhs_evaluations,
              stats.linear_iterations, stats.jacobian_vector_products, stats.jacobian_evaluations, stats.preconditioner_setups,
              stats.error_test_failures, stats.nonlinear_failures, stats.linear_convergence_failures);
  if (tail.m0.empty()) return 1;
  report(tail, start_mass, mass(last));
  return 0;
}
