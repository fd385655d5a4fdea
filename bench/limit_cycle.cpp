// Limit cycles below the Hopf curve by shooting (solvers/limit_cycle.hpp), and the criticality of the Hopf
// bifurcation from the amplitude law of the cycles just below it. For each a: the cycles at λ = 0.6, 0.7, 0.8,
// 0.9 and 0.95 λ_crit, each from a run of 16 linear periods and 12 e-folding times of the unstable focus (as
// the scan does; natural continuation from the cycle at the λ before failed: from 0.6 to 0.7 λ_crit at a = 0.95
// Newton stalled at a scaled residual of 2.6 after 57 period maps). Near a supercritical Hopf point the
// cycles are stable and A² = (max M0 − min M0)²/4 falls linearly to 0 at λ_crit; the least-squares line of A²
// against λ (gsl_fit_linear) over the three cycles nearest the curve gives the λ where it reaches 0, to compare
// with λ_crit from the spectrum (and over all of them, to show how far the linear law holds). A subcritical point would show unstable cycles on this
// side (|μ| > 1) or none.
//   bench_limit_cycle [--grid K,r] [a=lambda_crit ...]
// Default: the scan scene's model grid (K = 64, r = 1.05, N = 2^40) at a = 0.95, 0.8, 0.7 with the converged
// λ_crit of the scan's Hopf curve (K = 64, r = 1.02).
#include <gsl/gsl_fit.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <utility>
#include <vector>

#include "bench/figures.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/stability.hpp"
#include "solvers/steady_branch.hpp"

using namespace aggkit;

namespace {

struct Row {
  double fraction = 0, lambda = 0, period = NAN, amplitude = NAN, floquet = NAN, cpu = 0;
  bool converged = false, stable = false;
  int newton = 0;
  long maps = 0;
};

double cpu_now() { return double(std::clock()) / CLOCKS_PER_SEC; }

AggregationModel model_at(const SizeGrid& grid, double a, double lambda) {
  AggregationModel model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = std::size_t(1) << 40;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid = grid;
  return model;
}

// The cycle from a run whose length the spectrum sets (not converged, with the reason, where there is none).
LimitCycle first_cycle(const AggregationModel& model) {
  SteadyBranch branch(model, 0.1);
  const BranchSteadyState steady = branch.at(model.lambda(0.0));
  if (!steady.steady.converged) {
    LimitCycle none;
    none.note = "no steady state: " + steady.note;
    return none;
  }
  const StabilityResult spectrum = analyse_stability(model, steady.steady.n);
  const std::complex<double> mu = rightmost_complex_pair(spectrum.rightmost);
  const double period = 2 * M_PI / mu.imag(), settle = std::max(16 * period, 12 / mu.real());
  const std::optional<CycleStart> start = cycle_start_from_run(model, settle, period / 50);
  if (!start) {
    LimitCycle none;
    none.note = "the run does not oscillate";
    return none;
  }
  LimitCycleOptions options;
  options.tolerance = 1e-4;
  return find_limit_cycle(model, start->state, start->period, options);
}

Row row_of(const LimitCycle& c, double fraction, double lambda, double cpu) {
  Row r;
  r.fraction = fraction, r.lambda = lambda, r.cpu = cpu, r.converged = c.converged, r.stable = c.stable;
  r.period = c.period, r.amplitude = 0.5 * (c.m0_max - c.m0_min), r.newton = c.newton_iterations, r.maps = c.period_maps;
  if (!c.floquet.empty()) r.floquet = std::abs(c.floquet.front());
  return r;
}

void study(const SizeGrid& grid, double a, double lambda_crit, const aggkit::bench::Figures& figures) {
  std::printf("\na = %.2f, lambda_crit = %.6g (spectrum), grid %s\n", a, lambda_crit, grid.describe().c_str());
  std::printf("| lambda / lambda_crit | lambda | period | amplitude (M0) | largest |mu| | stable | Newton | period maps | CPU s |\n"
              "|---|---|---|---|---|---|---|---|---|\n");
  std::vector<Row> rows;
  for (double fraction : {0.6, 0.7, 0.8, 0.9, 0.95}) {
    const double lambda = fraction * lambda_crit;
    const AggregationModel model = model_at(grid, a, lambda);
    const double started = cpu_now();
    const LimitCycle c = first_cycle(model);
    const Row r = row_of(c, fraction, lambda, cpu_now() - started);
    std::printf("| %.2f | %.6g | %.6g | %.4g | %.4f | %s | %d | %ld | %.1f |%s%s\n", fraction, lambda, r.period, r.amplitude,
                r.floquet, r.stable ? "yes" : "no", r.newton, r.maps, r.cpu, c.converged ? "" : " NOT CONVERGED: ",
                c.converged ? "" : c.note.c_str());
    std::fflush(stdout);
    const std::string name = "a=" + aggkit::bench::Figures::text(a) + " lambda/lambda_crit=" + aggkit::bench::Figures::text(fraction);
    figures.add(name, "period", r.period, "1");
    figures.add(name, "cpu_seconds", r.cpu, "s");
    if (c.converged) rows.push_back(r);
  }
  if (rows.size() < 3) return;
  // A² is linear in λ only near the curve (the normal form's leading order): the line through the three cycles
  // nearest λ_crit is the estimate; the line through all of them shows how far the law holds.
  bool all_stable = true;
  for (const Row& r : rows) all_stable = all_stable && r.stable;
  for (std::size_t first : {rows.size() - 3, std::size_t(0)}) {
    std::vector<double> x, y;
    for (std::size_t i = first; i < rows.size(); ++i) x.push_back(rows[i].lambda), y.push_back(rows[i].amplitude * rows[i].amplitude);
    double c0 = 0, c1 = 0, cov00 = 0, cov01 = 0, cov11 = 0, sumsq = 0;
    gsl_fit_linear(x.data(), 1, y.data(), 1, x.size(), &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
    const double zero = -c0 / c1;
    std::printf("A^2 = %.4g + %.4g lambda over the %zu cycles nearest the curve: A^2 = 0 at lambda = %.6g (%+.2e from "
                "lambda_crit); slope %s, cycles %s: %s\n",
                c0, c1, x.size(), zero, zero / lambda_crit - 1, c1 < 0 ? "negative" : "positive",
                all_stable ? "stable" : "not all stable",
                c1 < 0 && all_stable ? "supercritical" : "not supercritical by this test");
    figures.add("a=" + aggkit::bench::Figures::text(a) + " cycles=" + std::to_string(x.size()),
                "amplitude_zero_over_lambda_crit", zero / lambda_crit, "1");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  std::vector<std::pair<double, double>> cases;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--grid" && i + 1 < argc) {
      const std::string value = argv[++i];
      grid.resolved = std::strtoul(value.c_str(), nullptr, 10);
      grid.ratio = std::atof(value.substr(value.find(',') + 1).c_str());
    } else if (const auto eq = arg.find('='); eq != std::string::npos) {
      cases.emplace_back(std::atof(arg.substr(0, eq).c_str()), std::atof(arg.substr(eq + 1).c_str()));
    } else {
      std::fprintf(stderr, "bench_limit_cycle: unknown argument %s (use --grid K,r and a=lambda_crit)\n", arg.c_str());
      return 2;
    }
  }
  if (cases.empty()) cases = {{0.95, 0.012670304269846413}, {0.8, 0.0036778704941043796}, {0.7, 0.00043910297364193164}};
  const aggkit::bench::Figures figures("limit_cycle", argc, argv);
  for (const auto& [a, lambda_crit] : cases) study(grid, a, lambda_crit, figures);
}
