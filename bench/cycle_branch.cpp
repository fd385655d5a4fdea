// The branch of limit cycles from the Hopf point down in λ (solvers/cycle_branch.hpp), and the Hopf normal
// form there (solvers/hopf_normal_form.hpp): per a, the first Lyapunov coefficient, the normal form's
// predicted M0 half-range against the shot cycle's at (1 − δ) λ_crit, then each λ asked for: period, M0 range,
// largest nontrivial Floquet multiplier, shooting solves on the way and CPU seconds.
//   bench_cycle_branch [--grid K,r] [--step h] [--tolerance t] a[=lambda_crit]:lambda1,lambda2,... ...
// (without "=lambda_crit": located on the model's own grid by hopf_on_branch)
//   bench_cycle_branch [--grid K,r] [--start δ] --criticality a1,a2,...   the normal form along the curve
// Default: the scan scene's model grid (K = 64, r = 1.05, N = 2^40), a = 0.95 and 0.7 with the converged
// λ_crit of the scan's Hopf curve, λ down the scan's half-decade column.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "bench/scan_model.hpp"
#include "solvers/cycle_branch.hpp"
#include "solvers/steady_branch.hpp"

using namespace aggkit;

namespace {

double cpu_now() { return double(std::clock()) / CLOCKS_PER_SEC; }

struct Case {
  double a = 0, lambda_crit = 0;
  std::vector<double> lambdas;
};

Case parse_case(const std::string& text) {
  Case c;
  const std::size_t eq = text.find('='), colon = text.find(':');
  c.a = std::stod(text.substr(0, std::min(eq, colon)));
  if (eq != std::string::npos) c.lambda_crit = std::stod(text.substr(eq + 1, colon - eq - 1));
  std::stringstream list(text.substr(colon + 1));
  for (std::string item; std::getline(list, item, ',');) c.lambdas.push_back(std::stod(item));
  return c;
}

void run_case(const SizeGrid& grid, const Case& c, const CycleBranchOptions& options) {
  const AggregationModel model = bench::scan_model(grid, c.a);
  SteadyBranch steady(model, 0.1);
  const double started = cpu_now();
  double lambda_crit = c.lambda_crit;
  if (!(lambda_crit > 0.0)) {
    const HopfPoint h = hopf_on_branch(steady, model, c.a, 1e-12);
    std::printf("a = %g: Hopf point on the branch's grid: %s lambda_crit = %.10g (omega %.6g), %d evaluations, %.1f s CPU %s\n",
                c.a, h.found ? "found" : "NOT found", h.lambda_crit, h.omega, h.evaluations, cpu_now() - started, h.note.c_str());
    std::fflush(stdout);
    if (!h.found) return;
    lambda_crit = h.lambda_crit;
  }
  CycleBranch branch(model, steady, lambda_crit, options);
  const HopfNormalForm& form = branch.normal_form();
  std::printf("a = %g, lambda_crit = %.10g, first cycle at %.10g: mu = %.4g %+.4gi, l1 = %.4g (c1 = %.4g %+.4gi), "
              "eigen residual %.2g, predicted M0 half-range %.4g, %.1f s CPU\n",
              c.a, lambda_crit, branch.start_lambda(), form.mu.real(), form.mu.imag(), form.lyapunov, form.c1.real(),
              form.c1.imag(), form.eigen_residual, form.m0_half_range(), cpu_now() - started);
  std::fflush(stdout);
  std::printf("%12s %12s %12s %12s %10s %8s %8s %8s %s\n", "lambda", "period", "M0 min", "M0 max", "|mu|max", "solves",
              "maps", "cpu s", "note");
  for (double lambda : c.lambdas) {
    const double t0 = cpu_now();
    const BranchCycle b = branch.at(lambda);
    const LimitCycle& y = b.cycle;
    std::printf("%12.5g %12.6g %12.6g %12.6g %10.4g %8d %8ld %8.1f %s%s\n", lambda, y.period, y.m0_min, y.m0_max,
                y.floquet.empty() ? NAN : std::abs(y.floquet.front()), b.solves, y.period_maps, cpu_now() - t0,
                y.converged ? "" : b.note.c_str(), y.converged ? "" : (" stopped at " + std::to_string(b.stopped_lambda)).c_str());
    std::printf("             Newton %d, GMRES %ld, residual %.3g, shooting %.1f s\n", y.newton_iterations, y.krylov_iterations,
                y.residual, y.seconds);
    std::fflush(stdout);
  }
}

// The criticality along the Hopf curve: per a, λ_crit on the model's own grid (hopf_on_branch) and the normal
// form at (1 − δ) λ_crit: l1, c1 and the predicted M0 half-range.
void criticality(const SizeGrid& grid, const std::vector<double>& a_values, double distance) {
  std::printf("%6s %16s %12s %12s %12s %12s %14s %10s %8s\n", "a", "lambda_crit", "omega", "l1", "Re c1", "Im c1",
              "M0 half-range", "at lambda", "cpu s");
  for (double a : a_values) {
    const double t0 = cpu_now();
    const AggregationModel model = bench::scan_model(grid, a);
    SteadyBranch steady(model, 0.1);
    const HopfPoint h = hopf_on_branch(steady, model, a, 1e-12);
    if (!h.found) {
      std::printf("%6g  no Hopf crossing: %s (%.1f s)\n", a, h.note.c_str(), cpu_now() - t0);
      std::fflush(stdout);
      continue;
    }
    CycleBranchOptions options;
    options.start_distance = distance;
    CycleBranch branch(model, steady, h.lambda_crit, options);
    const HopfNormalForm& form = branch.normal_form();
    std::printf("%6g %16.10g %12.6g %12.5g %12.5g %12.5g %14.5g %10.5g %8.1f %s\n", a, h.lambda_crit, h.omega, form.lyapunov,
                form.c1.real(), form.c1.imag(), form.m0_half_range(), branch.start_lambda(), cpu_now() - t0,
                form.q.empty() ? "no normal form" : form.supercritical() ? "supercritical" : "SUBCRITICAL");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  CycleBranchOptions options;
  std::vector<Case> cases;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--grid" && i + 1 < argc) {
      const std::string value = argv[++i];
      grid.resolved = std::size_t(std::stoul(value.substr(0, value.find(','))));
      grid.ratio = std::stod(value.substr(value.find(',') + 1));
    } else if (arg == "--step" && i + 1 < argc) {
      options.step = std::stod(argv[++i]);
    } else if (arg == "--criticality" && i + 1 < argc) {
      std::vector<double> a_values;
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) a_values.push_back(std::stod(item));
      criticality(grid, a_values, options.start_distance);
      return 0;
    } else if (arg == "--relax" && i + 1 < argc) {
      options.relax_periods = std::stod(argv[++i]);
    } else if (arg == "--start" && i + 1 < argc) {
      options.start_distance = std::stod(argv[++i]);
    } else if (arg == "--tolerance" && i + 1 < argc) {
      options.shooting.tolerance = std::stod(argv[++i]);
    } else {
      cases.push_back(parse_case(arg));
    }
  }
  if (cases.empty()) {
    cases.push_back(parse_case("0.95=0.012670304269846413:0.01,0.00316227766,0.001,0.000316227766,0.0001,3.16227766e-5,1e-5"));
    cases.push_back(parse_case("0.7=0.00043910297364193164:0.000316227766,0.0001,3.16227766e-5,1e-5,3.16227766e-6,1e-6"));
  }
  for (const Case& c : cases) run_case(grid, c, options);
  return 0;
}
