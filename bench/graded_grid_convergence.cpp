// The graded size grid (solvers/size_grid.hpp; four-moment shares by default, three-moment [Alopaeus2006] or
// fixed-pivot [Kumar1996] with --scheme) against exact solutions as
// r - 1 falls: constant kernel (λ = 0, t = 20 and 100), sum kernel (λ = 0, t = 3) and K = 2 with λ = 0.1 (t = 50),
// monodisperse unit start, drop truncation at N = 2^30 (no mass leaves at these times). Both schemes keep
// number and mass exactly, so M0 and M1 are exact on any grid for these kernels (M0 obeys a closed equation
// in M0 and M1); three-moment shares also keep x², and M2 obeys a closed equation in M1 and M2 for these
// kernels, so M2 is exact too; four-moment shares keep x³, and M3 is exact as well. What the grid costs
// shows in M2 (fixed pivot), M3 (three-moment) and in the densities of the sections. Prints, per r:
// classes, the relative errors of M0, M2 and M3, the largest relative error of n_k (the densities the
// numbers stand for, section_densities) over the pivots where n_k ≥ 1e-6 max n, and the orders
// log2(e(2(r-1)) / e(r-1)).
//   bench_graded_grid_convergence [--resolved K] [--rtol R] [--scheme four-moment|three-moment|fixed-pivot]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/exact_solutions.hpp"

using namespace aggkit;

namespace {

struct Case {
  std::string name;
  Kernel kernel;
  double lambda;
  double t;
};

struct Errors {
  std::size_t classes = 0;
  double m0 = 0, m2 = 0, m3 = 0, density = 0, seconds = 0;
};

Errors run(const Case& c, std::size_t K, double r, double rtol, GridScheme scheme) {
  AggregationModel model;
  model.kernel = c.kernel;
  model.lambda = ShatteringRate::constant(c.lambda);
  model.size = std::size_t(1) << 30;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid.resolved = K;
  model.grid.ratio = r;
  model.grid.scheme = scheme;
  IntegratorOptions options;
  options.rtol = rtol;
  const std::vector<double> x = model.pivots();
  std::vector<double> n;
  const double times[] = {c.t};
  const IntegratorStatistics s = integrate(model, times, options, [&](double, std::span<const double> v, double) { n.assign(v.begin(), v.end()); });
  Errors e;
  e.classes = x.size();
  e.seconds = s.wall_seconds;
  double m0 = 0, m2 = 0, m3 = 0;
  for (std::size_t i = 0; i < x.size(); ++i) m0 += n[i], m2 += x[i] * x[i] * n[i], m3 += x[i] * x[i] * x[i] * n[i];
  double exact_m0 = 0, exact_m2 = 0, exact_m3 = NAN;
  if (c.name == "K=2") {
    exact_m0 = exact_total_density_k2(c.lambda, c.t);
    exact_m2 = NAN;  // no closed form with shattering
  } else {
    exact_m0 = exact_moment(c.name, 0, c.t);
    exact_m2 = exact_moment(c.name, 2, c.t);
    exact_m3 = exact_moment(c.name, 3, c.t);
  }
  e.m0 = std::abs(m0 / exact_m0 - 1);
  e.m2 = std::abs(m2 / exact_m2 - 1);
  e.m3 = std::abs(m3 / exact_m3 - 1);
  if (c.name != "K=2") {
    const std::vector<double> density = section_densities(x, n, scheme, K);
    double largest = 0;
    for (std::size_t i = 0; i < x.size() && x[i] < 1e6; ++i) largest = std::max(largest, exact_density(c.name, std::size_t(x[i]), c.t));
    for (std::size_t i = 0; i < x.size() && x[i] < 1e6; ++i) {
      const double exact = exact_density(c.name, std::size_t(x[i]), c.t);
      if (exact >= 1e-6 * largest) e.density = std::max(e.density, std::abs(density[i] / exact - 1));
    }
  } else {
    e.density = NAN;
  }
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t K = 8;
  double rtol = 1e-10;
  GridScheme scheme = GridScheme::four_moment;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--resolved" && i + 1 < argc) K = std::strtoul(argv[++i], nullptr, 10);
    else if (arg == "--rtol" && i + 1 < argc) rtol = std::atof(argv[++i]);
    else if (arg == "--scheme" && i + 1 < argc) scheme = scheme_from_name(argv[++i]);
    else {
      std::fprintf(stderr, "usage: bench_graded_grid_convergence [--resolved K] [--rtol R] [--scheme four-moment|three-moment|fixed-pivot]\n");
      return 2;
    }
  }
  const aggkit::bench::Figures figures("graded_grid_convergence", argc, argv);
  const std::vector<Case> cases = {{"constant", Kernel::constant(), 0.0, 20.0},
                                   {"constant", Kernel::constant(), 0.0, 100.0},
                                   {"sum", Kernel::sum(), 0.0, 3.0},
                                   {"K=2", Kernel::brownian(0.0), 0.1, 50.0}};
  const double ratios[] = {1.4, 1.2, 1.1, 1.05, 1.025, 1.0125};
  std::printf("K = %zu, N = 2^30, drop, rtol %g, %s shares\n", K, rtol, scheme_name(scheme));
  for (const Case& c : cases) {
    std::printf("\n%s kernel, lambda = %g, t = %g\n| r | classes | M0 error | M2 error | order M2 | M3 error | order M3 | max n_k error | order n_k | wall s |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n",
                c.name.c_str(), c.lambda, c.t);
    Errors previous;
    for (double r : ratios) {
      const Errors e = run(c, K, r, rtol, scheme);
      const double order_m2 = previous.classes ? std::log2(previous.m2 / e.m2) : NAN;
      const double order_m3 = previous.classes ? std::log2(previous.m3 / e.m3) : NAN;
      const double order_n = previous.classes ? std::log2(previous.density / e.density) : NAN;
      std::printf("| %.4g | %zu | %.2e | %.2e | %.2f | %.2e | %.2f | %.2e | %.2f | %.2f |\n", r, e.classes, e.m0, e.m2, order_m2,
                  e.m3, order_m3, e.density, order_n, e.seconds);
      std::fflush(stdout);
      const std::string name = c.name + " t=" + aggkit::bench::Figures::text(c.t) + " r=" + aggkit::bench::Figures::text(r);
      figures.add(name, "m2_error", e.m2, "1");
      figures.add(name, "density_error", e.density, "1");
      figures.add(name, "m0_error", e.m0, "1");
      figures.add(name, "m3_error", e.m3, "1");
      previous = e;
    }
  }
}
