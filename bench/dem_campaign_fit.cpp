// The logistic fit of the DEM campaign's dissipation threshold [Trivino2025, Fig. 4]: C/N_tot against log10 γ_n
// from an `aggkit sweep` sweep.csv (one row per run), y = low + (high − low)/(1 + exp((log10 γ − m)/w)),
// by GSL nonlinear least squares (analysis/logistic_fit.hpp). Prints the plateaus and the midpoint
// γ_50 = 10^m with its error, and γ_50 read in the candidate units of the paper's unstated γ_n (k̃_n given):
//   bench_dem_campaign_fit sweep.csv [x column (engine.damping)] [y column (components_fraction)] [k̃_n (1e6)]
// Figures (bench/figures.hpp): gamma_50, its one-sigma range in log10, the plateaus, case "k_n=<k̃_n>".
// Units G = m = R = 1: γ_n in √(G m³/R³); m/t_c with t_c = π √(m_eff/k_n), m_eff = m/2 [Trivino2025, eq. 8];
// √(k_n m); per reduced mass (γ_n/m*, the convention of LAMMPS' gran/hooke).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/logistic_fit.hpp"
#include "bench/figures.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " sweep.csv [x column] [y column] [k̃_n]\n";
    return 2;
  }
  const std::string x_name = argc > 2 ? argv[2] : "engine.damping";
  const std::string y_name = argc > 3 ? argv[3] : "components_fraction";
  const double k = argc > 4 ? std::stod(argv[4]) : 1e6;
  std::ifstream in(argv[1]);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) header.push_back(c);
  }
  int xi = -1, yi = -1;
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == x_name) xi = int(i);
    if (header[i] == y_name) yi = int(i);
  }
  if (xi < 0 || yi < 0) {
    std::cerr << "columns " << x_name << " and " << y_name << " are needed in " << argv[1] << "\n";
    return 2;
  }
  std::vector<double> x, y;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string c; std::getline(fields, c, ',');) cells.push_back(c);
    x.push_back(std::log10(std::stod(cells[std::size_t(xi)])));
    y.push_back(std::stod(cells[std::size_t(yi)]));
  }
  const aggkit::LogisticFit fit = aggkit::fit_logistic(x, y);
  const aggkit::bench::Figures figures("dem_campaign_fit", argc, argv);
  const std::string case_name = "k_n=" + aggkit::bench::Figures::text(k) + " y=" + y_name;
  std::printf("logistic fit of %s against log10 %s over %zu runs: %s\n", y_name.c_str(), x_name.c_str(), x.size(),
              fit.converged ? "converged" : "NOT determined (the step falls between grid values: only bracketed)");
  std::printf("  high plateau %.4f ± %.4f, low plateau %.4f ± %.4f, width %.3f ± %.3f decades, rms residual %.3g\n", fit.high,
              fit.high_error, fit.low, fit.low_error, fit.width, fit.width_error,
              std::sqrt(fit.residual_sum_of_squares / double(x.size())));
  const double g50 = std::pow(10.0, fit.midpoint);
  const double low = std::pow(10.0, fit.midpoint - fit.midpoint_error), high = std::pow(10.0, fit.midpoint + fit.midpoint_error);
  std::printf("  midpoint log10 γ = %.3f ± %.3f: γ_50 = %.4g (one-sigma range %.4g – %.4g) in units √(G m³/R³)\n", fit.midpoint,
              fit.midpoint_error, g50, low, high);
  figures.add(case_name, "gamma_50", g50, "sqrt(G m^3/R^3)");
  figures.add(case_name, "log10_gamma_50_error", fit.midpoint_error, "1");
  figures.add(case_name, "high_plateau", fit.high, "1");
  figures.add(case_name, "low_plateau", fit.low, "1");
  const double m_eff = 0.5, t_c = M_PI * std::sqrt(m_eff / k);
  const double zeta = g50 / (2 * std::sqrt(k * m_eff));
  std::printf("  at k̃_n = %g: damping ratio ζ_50 = %.4f, formula restitution e = %.3f\n", k, zeta,
              zeta < 1 ? std::exp(-zeta * M_PI / std::sqrt(1 - zeta * zeta)) : 0.0);
  std::printf("  γ_50 in other readings of the paper's unit (published threshold ≈ 500):\n");
  std::printf("    γ/√(G m³/R³)  %.4g\n", g50);
  std::printf("    γ/(m/t_c)     %.4g   (t_c = %.4g)\n", g50 / (1.0 / t_c), t_c);
  std::printf("    γ/√(k_n m)    %.4g\n", g50 / std::sqrt(k));
  std::printf("    γ/m*          %.4g   (γ per reduced mass, LAMMPS' gran/hooke)\n", g50 / m_eff);
  return fit.converged ? 0 : 1;
}
