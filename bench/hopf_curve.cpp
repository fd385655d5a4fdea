// λ_crit(a) of the brownian kernel (i/j)^a + (j/i)^a ([Kalinov2022, Sec. 5.2]) by locate_hopf:
// a = 0.55 … 1.0 step 0.05, cutoff truncation, monodisperse unit mass, λ bracket [lo, hi] (default
// [1e-4, 1]; at N = 8192 the quasi-steady state does not exist below λ ≈ 1e-3, so use --lo 0.003),
// relative tolerance 1e-3. Prints per a:
// λ_crit, its bracket, ω and the period 2π/ω, evaluations, seconds; then the total time.
//   bench_hopf_curve [N] [--a A ...] [--lo L] [--hi H] [--dense] [--tol T] [--spectrum LAMBDA]  (--spectrum: only print the
//   rightmost eigenvalues at that λ for each a, dense and Krylov)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "solvers/stability.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  std::size_t N = 8192;
  std::vector<double> as;
  double tolerance = 1e-3, spectrum_lambda = 0.0, lo = 1e-4, hi = 1.0;
  HopfOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--a" && i + 1 < argc) as.push_back(std::atof(argv[++i]));
    else if (arg == "--lo" && i + 1 < argc) lo = std::atof(argv[++i]);
    else if (arg == "--hi" && i + 1 < argc) hi = std::atof(argv[++i]);
    else if (arg == "--dense") options.stability.method = SpectrumMethod::dense;
    else if (arg == "--tol" && i + 1 < argc) tolerance = std::atof(argv[++i]);
    else if (arg == "--spectrum" && i + 1 < argc) spectrum_lambda = std::atof(argv[++i]);
    else N = std::strtoul(arg.c_str(), nullptr, 10);
  }
  if (as.empty())
    for (int i = 0; i <= 9; ++i) as.push_back(0.55 + 0.05 * i);
  AggregationModel base;
  base.size = N;
  base.truncation = Truncation::cutoff;
  base.initial = monodisperse(N);
  if (spectrum_lambda > 0.0) {
    for (double a : as) {
      AggregationModel model = base;
      model.kernel = Kernel::brownian(a);
      model.lambda = ShatteringRate::constant(spectrum_lambda);
      const SteadyStateResult steady = solve_steady_state(model, options.steady);
      std::printf("a = %g, lambda = %g: steady %s in %.2f s (residual %.1e)\n", a, spectrum_lambda,
                  steady.converged ? "converged" : "FAILED", steady.seconds, steady.relative_residual);
      for (SpectrumMethod method : {SpectrumMethod::dense, SpectrumMethod::krylov}) {
        if (method == SpectrumMethod::dense && N > 3000) continue;
        StabilityOptions so = options.stability;
        so.method = method;
        const StabilityResult r = analyse_stability(model, steady.n, 8, so);
        std::printf("  %-6s %.2f s (%d solves, %ld GMRES):", r.method.c_str(), r.seconds, r.operator_applications,
                    r.linear_iterations);
        for (auto mu : r.rightmost) std::printf(" (%.6g, %.6g)", mu.real(), mu.imag());
        std::printf("\n");
      }
    }
    return 0;
  }
  std::printf("N = %zu, cutoff, tolerance %g\n| a | lambda_crit | bracket | omega | period 2pi/omega | evaluations | seconds | note |\n|---|---|---|---|---|---|---|---|\n", N, tolerance);
  const auto started = std::chrono::steady_clock::now();
  const aggkit::bench::Figures figures("hopf_curve", argc, argv);
  for (double a : as) {
    const HopfPoint p = locate_hopf(base, a, lo, hi, tolerance, options);
    std::printf("| %.2f | %.6g | %.1e | %.6g | %.5g | %d | %.1f | %s |\n", a, p.lambda_crit, p.lambda_tolerance, p.omega,
                p.omega > 0 ? 2 * M_PI / p.omega : 0.0, p.evaluations, p.seconds, p.note.c_str());
    const std::string case_name = "a=" + aggkit::bench::Figures::text(a) + " N=" + std::to_string(N);
    figures.add(case_name, "lambda_crit", p.lambda_crit, "1");
    figures.add(case_name, "seconds", p.seconds, "s");
    std::fflush(stdout);
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf("total %.1f s\n", total);
  figures.add("N=" + std::to_string(N) + " curve of " + std::to_string(as.size()) + " a", "wall_seconds", total, "s");
}
