// Stress runs of the CVODE solver: long times (t = 10^4), strong shattering (λ up to 10) and
// large truncations (N up to 2^17). For each run: wall time, steps, the conservation defect (cutoff:
// |M1 - M1(0)|; drop: |M1 + leaked - M1(0)|), negative densities at the end, and any failure.
//   bench_stress [--quick | --large]   (--quick: N = 4096; --large: N = 2^15..2^17 without the slow
//   λ = 0.01 runs of the ballistic and Brownian kernels)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {

struct Case {
  Kernel kernel;
  double lambda;
  std::size_t N;
  Truncation truncation;
};

void run_case(const Case& c, double t_end, const aggkit::bench::Figures& figures) {
  AggregationModel model;
  model.kernel = c.kernel;
  model.lambda = ShatteringRate::constant(c.lambda);
  model.size = c.N;
  model.truncation = c.truncation;
  model.initial = monodisperse(c.N);
  IntegratorOptions options;
  options.max_steps = 200000;  // all else default
  std::vector<double> outputs{1.0, 10.0, 100.0, 1000.0, t_end};
  double drift = 0.0, m0 = 0.0, m2 = 0.0, reached = 0.0;
  std::size_t negatives = 0;
  double most_negative = 0.0;
  std::string failure;
  IntegratorStatistics stats;
  const auto start = std::chrono::steady_clock::now();
  try {
    stats = integrate(model, outputs, options, [&](double t, std::span<const double> n, double leaked) {
      drift = std::max(drift, std::abs(moment(n, 1.0) + leaked - 1.0));
      m0 = moment(n, 0.0), m2 = moment(n, 2.0), reached = t;
      negatives = 0;
      for (double x : n)
        if (x < 0.0) ++negatives, most_negative = std::min(most_negative, x);
    });
  } catch (const std::exception& e) {
    failure = e.what();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("| %-16s | %5g | %6zu | %-6s | %7.2f | %6ld | %8.1e | %5zu | %9.1e | %9.3e | %9.3e | %s |\n",
              c.kernel.describe().c_str(), c.lambda, c.N, to_string(c.truncation).c_str(), wall, stats.steps, drift,
              negatives, most_negative, m0, m2,
              failure.empty() ? "ok" : ("failed at t = " + std::to_string(reached) + ": " + failure.substr(0, 80)).c_str());
  std::fflush(stdout);
  const std::string case_name = c.kernel.describe() + " lambda=" + aggkit::bench::Figures::text(c.lambda) +
                                " N=" + std::to_string(c.N) + " " + to_string(c.truncation);
  figures.add(case_name, "wall_seconds", failure.empty() ? wall : std::nan(""), "s");
  figures.add(case_name, "mass_defect", drift, "1");
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool large = argc > 1 && std::strcmp(argv[1], "--large") == 0;
  const double t_end = 1e4;
  std::printf("default options (bdf-gmres + monomer preconditioner, rtol 1e-6, atol 1e-8/k^3 >= 1e-16), t = 0 .. %g\n\n", t_end);
  std::printf("| kernel | lambda | N | trunc. | wall [s] | steps | mass defect | #neg | most neg. | M0(end) | M2(end) | status |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<Case> cases;
  // N = 2^17 for the exact rank-1/2 kernels; the ballistic kernel (rank ~25) up to 2^15 here.
  const std::vector<std::size_t> sizes = quick ? std::vector<std::size_t>{4096} : std::vector<std::size_t>{4096, 32768, 131072};
  for (std::size_t N : sizes)
    for (double lambda : {0.01, 1.0, 10.0}) {
      cases.push_back({Kernel::constant(), lambda, N, Truncation::cutoff});
      if (N <= 32768) cases.push_back({Kernel::ballistic(), lambda, N, Truncation::drop});
      cases.push_back({Kernel::brownian(0.95), lambda, N, Truncation::cutoff});
    }
  if (large) {
    cases.clear();
    for (double lambda : {0.01, 1.0, 10.0}) cases.push_back({Kernel::constant(), lambda, 131072, Truncation::cutoff});
    for (double lambda : {1.0, 10.0}) cases.push_back({Kernel::brownian(0.95), lambda, 131072, Truncation::cutoff});
    for (double lambda : {1.0, 10.0}) cases.push_back({Kernel::ballistic(), lambda, 32768, Truncation::drop});
  }
  const aggkit::bench::Figures figures("stress", argc, argv);
  for (const auto& c : cases) run_case(c, t_end, figures);
  return 0;
}
