// Dilute 2-D ballistic aggregation ([Gonzalez2011, Sec. 3.1]): kinetic energy E(t) and
// mean cluster size S(t) = N/C, fitted as E ∝ t^{-δ} and S ∝ t^{ζ} (mean field: ζ = 1 in 2-D) by least squares
// in log-log over t in [T1, T2] (log-spaced outputs), with the standard error of the slope.
//   bench_ed_decay N NU THERMALIZE T1 T2 [SEED]   (periodic, uniform velocity components, zero momentum)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "analysis/least_squares.hpp"
#include "bench/ed_common.hpp"
#include "bench/figures.hpp"

using namespace aggkit;

namespace {

struct Fit {
  double slope, error;
};

// Least squares in log-log (analysis/least_squares.hpp, gsl_fit_linear): slope and its standard error
// sqrt(Σ residual² / (n - 2) / Σ (x - x̄)²).
Fit fit_loglog(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> lx(x.size()), ly(y.size());
  for (std::size_t i = 0; i < x.size(); ++i) lx[i] = std::log(x[i]), ly[i] = std::log(y[i]);
  const LineFit f = fit_line(lx, ly);
  return {f.slope, f.slope_error};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s N NU THERMALIZE T1 T2 [SEED]\n", argv[0]);
    return 2;
  }
  const auto n = std::size_t(std::atof(argv[1]));
  const double nu = std::atof(argv[2]);
  const auto thermalize = std::size_t(std::atoi(argv[3]));
  const double t1 = std::atof(argv[4]), t2 = std::atof(argv[5]);
  const std::uint64_t seed = argc > 6 ? std::uint64_t(std::atoll(argv[6])) : 1;
  bench::print_load();
  auto ed = bench::make_ed(2, n, nu, Boundary::periodic, true, seed, VelocityLaw::uniform_components);
  const auto start = std::chrono::steady_clock::now();
  ed.thermalize(thermalize);  // on the elastic gas, then sticking from t = 0
  const double e0 = ed.kinetic_energy();
  std::printf("# N %zu nu %g periodic, thermalised %zu collisions/particle; t E/E0 S=N/C\n", n, nu, thermalize);
  std::vector<double> ts, es, ss;
  const double t_first = t1 / 100;
  for (double t = t_first; t <= t2 * 1.0001 && ed.clusters() > 1; t *= std::pow(10.0, 0.1)) {
    ed.advance(t, 1);
    const double e = ed.kinetic_energy() / e0, s = double(n) / double(ed.clusters());
    std::printf("%12.5g %12.5g %12.5g\n", t, e, s);
    if (t >= t1 * 0.9999) {
      ts.push_back(t);
      es.push_back(e);
      ss.push_back(s);
    }
  }
  const double seconds = bench::seconds_since(start);
  if (ts.size() >= 3) {
    const Fit e = fit_loglog(ts, es), s = fit_loglog(ts, ss);
    std::printf("# fit t in [%g, %g], %zu points: delta = %.3f +- %.3f, zeta = %.3f +- %.3f\n", ts.front(), ts.back(),
                ts.size(), -e.slope, e.error, s.slope, s.error);
    const bench::Figures figures("ed_decay", argc, argv);
    const std::string case_name = "N=" + bench::Figures::text(double(n)) + " nu=" + bench::Figures::text(nu);
    figures.add(case_name, "energy_decay_exponent", -e.slope, "1");
    figures.add(case_name, "size_growth_exponent", s.slope, "1");
    figures.add(case_name, "wall_seconds", seconds, "s");
  }
  std::printf("# %.1f s, %llu events\n", seconds, (unsigned long long)ed.counters().events());
  bench::print_load();
}
