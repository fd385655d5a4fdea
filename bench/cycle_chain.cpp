// The attracting cycle followed down a column of λ by time series alone: at the first λ (just below λ_crit) the
// run starts on the Hopf normal form's cycle; at each next λ it starts from the state the run before ended in
// (on the cycle of the λ above), runs `periods` predicted periods at rtol 1e-6 and measures the period from the
// crossings of its second half. Prints per λ: CPU seconds, period, crossings, M0 range, and the spread of the
// last periods (how settled the run is).
//   bench_cycle_chain a lambda_crit lambda_first lambda_last [periods] [ratio] [atol_floor] [max_steps]
// (λ divided by ratio each step, default sqrt(10); atol_floor the integrator's, default 0: its own; max_steps
// the CVODE steps one run may take, default 40000)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "analysis/crossing_periods.hpp"
#include "bench/scan_model.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/steady_branch.hpp"

using namespace aggkit;

namespace {
double cpu_now() { return double(std::clock()) / CLOCKS_PER_SEC; }
}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: bench_cycle_chain a lambda_crit lambda_first lambda_last [periods]\n");
    return 2;
  }
  const double a = std::atof(argv[1]), lambda_crit = std::atof(argv[2]);
  double lambda = std::atof(argv[3]);
  const double last = std::atof(argv[4]);
  const double periods = argc > 5 ? std::atof(argv[5]) : 14.0;
  const double ratio = argc > 6 ? std::atof(argv[6]) : std::sqrt(10.0);
  const double floor = argc > 7 ? std::atof(argv[7]) : 0.0;
  const long max_steps = argc > 8 ? std::atol(argv[8]) : 40000;
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  AggregationModel model = bench::scan_model(grid, a);
  SteadyBranch steady(model, 0.1);
  const double near = 0.95 * lambda_crit;
  model.lambda = ShatteringRate::constant(near);
  const BranchSteadyState s = steady.at(near);
  const HopfNormalForm form = hopf_normal_form(model, s.steady.n);
  std::vector<double> from = form.cycle_point(s.steady.n);
  double period = 2.0 * M_PI / form.mu.imag();
  double t_end = std::log(1e3) / (2.0 * form.mu.real()) + 16.0 * period;
  std::printf("a = %g: normal form at %.6g, period %.5g, run %.4g\n", a, near, period, t_end);
  std::printf("%12s %10s %10s %12s %6s %10s %10s %10s\n", "lambda", "t_end", "cpu s", "period", "cross", "M0 min", "M0 max", "spread");
  std::fflush(stdout);
  model.lambda = ShatteringRate::constant(near);
  bool first = true;
  while (lambda >= last * 0.999) {
    if (!first) model.lambda = ShatteringRate::constant(lambda);
    const double t0 = cpu_now();
    std::optional<CycleStart> start;
    try {
      for (double& n : from) n = std::max(n, 0.0);
      start = cycle_start_from_run(model, t_end, period / 50.0, 1e-6, from, max_steps, RunTolerance{.atol_floor = floor});
    } catch (const std::exception& e) {
      std::printf("%12.5g %10.4g %10.1f  failed: %s\n", first ? near : lambda, t_end, cpu_now() - t0, e.what());
      return 1;
    }
    if (!start) {
      std::printf("%12.5g %10.4g %10.1f  no oscillation\n", first ? near : lambda, t_end, cpu_now() - t0);
      return 1;
    }
    // The spread of the second half's periods between upward crossings of M0's mid-range.
    const CrossingPeriods c = crossing_periods(start->times, start->m0);
    double spread = NAN;
    if (c.periods.size() >= 2) {
      const auto [shortest, longest] = std::minmax_element(c.periods.begin(), c.periods.end());
      spread = (*longest - *shortest) / start->period;
    }
    std::printf("%12.5g %10.4g %10.1f %12.6g %6d %10.4g %10.4g %10.2g\n", first ? near : lambda, t_end, cpu_now() - t0,
                start->period, start->crossings, c.lowest, c.highest, spread);
    std::fflush(stdout);
    from = start->state;
    if (!first) lambda /= ratio;
    first = false;
    period = (first ? 1.0 : ratio) * start->period;
    t_end = periods * period;
  }
  return 0;
}
