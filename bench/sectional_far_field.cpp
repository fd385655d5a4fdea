// The separable far field of the sectional rates (solvers/sectional_far_field.hpp) against the pair loop alone,
// in one run: the Brownian-type kernel as Kernel::brownian (exact factors: the far field) and as a user kernel
// with the same formula (no factors: every pair summed one by one, the code before the far field).
//   bench_sectional_far_field [a lambda t_end]
// 1. CPU per right-hand side and per J·v on the scan's grid (K = 64, r = 1.05, N = 2^40) and on its Hopf grid
//    (r = 1.02), the two kernels interleaved, and the largest difference of J·v relative to |J||v|.
// 2. A run as the scan's cycle columns make them (rtol 1e-6, atol 1e-16, atol_floor 1e-16, atol_mass 1e-15) from
//    the monodisperse start to t_end (default a = 0.9, λ = 1e-4, t_end = 3e4: relaxation oscillations far
//    below λ_crit = 0.0096), with each kernel: CPU, CVODE steps, and M0 at the end.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "bench/scan_model.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/discretisation.hpp"

using namespace aggkit;

namespace {

double cpu_now() { return double(std::clock()) / CLOCKS_PER_SEC; }

Kernel pair_loop_brownian(double a) {
  return Kernel::user("brownian-as-user", [a](double i, double j) { return std::pow(i / j, a) + std::pow(j / i, a); });
}

// A state over 30 decades: n ∝ x^-(1 + a) e^{-x/1e10} per unit size.
std::vector<double> wide_state(const std::vector<double>& x, double a) {
  const std::vector<double> width = pivot_widths(x);
  std::vector<double> n(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) n[i] = std::pow(x[i], -1.0 - a) * std::exp(-x[i] / 1e10) * width[i];
  return n;
}

void per_call(const SizeGrid& grid, double a, const bench::Figures& figures) {
  AggregationModel fast = bench::scan_model(grid, a), loop = fast;
  loop.kernel = pair_loop_brownian(a);
  const auto d_fast = make_discretisation(fast), d_loop = make_discretisation(loop);
  const std::vector<double> n = wide_state(d_fast->sizes(), a);
  const std::size_t M = n.size();
  auto r_fast = d_fast->rates(RatesPath::direct), r_loop = d_loop->rates(RatesPath::direct);
  std::vector<double> v(M), out(M), out_loop(M);
  for (std::size_t i = 0; i < M; ++i) v[i] = (i % 3 == 0 ? -0.5 : 1.0) * n[i];
  const int reps = 2000;
  double cpu[2][2] = {};  // [fast, loop][rhs, jv]
  for (int round = 0; round < 4; ++round)
    for (int which = 0; which < 2; ++which) {
      Rates& r = which == 0 ? *r_fast : *r_loop;
      double t0 = cpu_now();
      for (int k = 0; k < reps; ++k) r.evaluate(0.0, n, out);
      cpu[which][0] += cpu_now() - t0;
      t0 = cpu_now();
      for (int k = 0; k < reps; ++k) r.jacobian_times(0.0, n, v, out);
      cpu[which][1] += cpu_now() - t0;
    }
  r_fast->jacobian_times(0.0, n, v, out);
  r_loop->jacobian_times(0.0, n, v, out_loop);
  double worst = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < M; ++k) scale = std::max(scale, std::abs(out_loop[k]));
  for (std::size_t k = 0; k < M; ++k) worst = std::max(worst, std::abs(out[k] - out_loop[k]) / scale);
  const double calls = 4.0 * reps;
  std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.1e |\n", grid.describe().c_str(), M,
              1e6 * cpu[1][0] / calls, 1e6 * cpu[0][0] / calls, cpu[1][0] / cpu[0][0], 1e6 * cpu[1][1] / calls,
              1e6 * cpu[0][1] / calls, cpu[1][1] / cpu[0][1], worst);
  const std::string name = "grid " + grid.describe() + " N=2^40 a=" + bench::Figures::text(a);
  figures.add(name, "rhs_speedup", cpu[1][0] / cpu[0][0], "x");
  figures.add(name, "jv_speedup", cpu[1][1] / cpu[0][1], "x");
  figures.add(name, "rhs_microseconds", 1e6 * cpu[0][0] / calls, "us");
  std::printf("   %s\n", r_fast->describe().c_str());
}

struct RunResult {
  double cpu = 0, m0 = 0;
  long steps = 0;
};

RunResult cycle_run(const Kernel& kernel, double a, double lambda, double t_end) {
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  AggregationModel model = bench::scan_model(grid, a);
  model.kernel = kernel;
  model.lambda = ShatteringRate::constant(lambda);
  IntegratorOptions options;
  options.rtol = 1e-6;
  options.atol = 1e-16;
  options.atol_floor = 1e-16;
  options.atol_mass = 1e-15;
  options.project_mass = false;
  const double times[] = {t_end};
  RunResult result;
  const double t0 = cpu_now();
  const IntegratorStatistics stats = integrate(model, times, options, [&](double, std::span<const double> n, double) {
    for (double v : n) result.m0 += v;
  });
  result.cpu = cpu_now() - t0;
  result.steps = stats.steps;
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  const double a = argc > 1 ? std::atof(argv[1]) : 0.9, lambda = argc > 2 ? std::atof(argv[2]) : 1e-4;
  const double t_end = argc > 3 ? std::atof(argv[3]) : 3e4;
  const bench::Figures figures("sectional_far_field", argc, argv);
  std::printf("CPU per call (µs), 4 × 2000 calls of each, interleaved; brownian a = %.3g\n", a);
  std::printf("| grid | M | rhs: pair loop | far field | speedup | J·v: pair loop | far field | speedup | max |ΔJv| / max |Jv| |\n"
              "|---|---|---|---|---|---|---|---|---|\n");
  for (double ratio : {1.05, 1.02}) {
    SizeGrid grid;
    grid.resolved = 64;
    grid.ratio = ratio;
    per_call(grid, a, figures);
  }
  std::printf("\nA cycle-column run: a = %.3g, lambda = %.3g, monodisperse start to t = %.3g, rtol 1e-6, atol 1e-16\n", a,
              lambda, t_end);
  std::printf("| kernel | CPU s | CVODE steps | M0 at t_end |\n|---|---|---|---|\n");
  RunResult runs[2];
  for (int which : {0, 1, 0, 1}) {
    const RunResult r = cycle_run(which == 0 ? Kernel::brownian(a) : pair_loop_brownian(a), a, lambda, t_end);
    std::printf("| %s | %.2f | %ld | %.12g |\n", which == 0 ? "far field" : "pair loop", r.cpu, r.steps, r.m0);
    std::fflush(stdout);
    runs[which].cpu += r.cpu, runs[which].steps = r.steps, runs[which].m0 = r.m0;
  }
  std::printf("run speedup %.2f x (CPU, both runs of each), M0 at t_end differs by %.2e relative\n", runs[1].cpu / runs[0].cpu,
              std::abs(runs[0].m0 - runs[1].m0) / runs[1].m0);
  const std::string name = "cycle run a=" + bench::Figures::text(a) + " lambda=" + bench::Figures::text(lambda) +
                           " t_end=" + bench::Figures::text(t_end);
  figures.add(name, "run_speedup", runs[1].cpu / runs[0].cpu, "x");
  figures.add(name, "far_field_cpu_seconds", runs[0].cpu / 2, "s");
}
