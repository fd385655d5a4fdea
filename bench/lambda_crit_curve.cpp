// λ_crit(a) of the brownian kernel (i/j)^a + (j/i)^a ([Kalinov2022, Sec. 5.2]) converged in the truncation N
// (solvers/hopf_curve.hpp): continuation in a from the top (default a = 1.0, 0.95, …, 0.55), N doubled until
// λ_crit changes by ≤ 1 % (--convergence), cutoff truncation, monodisperse unit mass. Prints per a:
// λ_crit at the largest N, that N, λ_crit at N/2 and the relative change (the truncation error bar), Brent's
// bracket, ω, evaluations, wall and CPU seconds; then the totals and the load average.
//   bench_lambda_crit_curve [--a A ...] [--guess L] [--size N] [--min-size N] [--max-size N] [--size-per-inverse-lambda S] [--convergence C] [--tol T] [--slope S]
//                           [--resolved K --ratio R [--scheme four-moment|three-moment|fixed-pivot]]
// (--resolved/--ratio: the graded grid of solvers/size_grid.hpp; each λ_crit is then also repeated with K doubled
// and with r - 1 halved, and the changes are printed beside the N/2 -> N one)
// (--slope: d ln λ_crit/da for the second point's guess, e.g. 16.7 from the N = 8192 values at a = 0.75, 0.8)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "solvers/hopf_curve.hpp"

using namespace aggkit;

namespace {
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<double> as;
  double guess = 0.015;  // λ_crit(1) at N = 8192 is 0.01538 (bench/results/RESULTS.md)
  std::size_t size = 1024;
  HopfCurveOptions options;
  SizeGrid grid;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&] { return i + 1 < argc ? argv[++i] : (std::fprintf(stderr, "%s needs a value\n", arg.c_str()), std::exit(2), argv[0]); };
    if (arg == "--a") as.push_back(std::atof(next()));
    else if (arg == "--guess") guess = std::atof(next());
    else if (arg == "--size") size = std::strtoul(next(), nullptr, 10);
    else if (arg == "--max-size") options.max_size = std::strtoul(next(), nullptr, 10);
    else if (arg == "--min-size") options.min_size = std::strtoul(next(), nullptr, 10);
    else if (arg == "--size-per-inverse-lambda") options.size_per_inverse_lambda = std::atof(next());
    else if (arg == "--convergence") options.convergence = std::atof(next());
    else if (arg == "--slope") options.log_slope = std::atof(next());
    else if (arg == "--tol") options.relative_tolerance = std::atof(next());
    else if (arg == "--bracket") options.bracket = std::atof(next());
    else if (arg == "--resolved") grid.resolved = std::strtoul(next(), nullptr, 10);
    else if (arg == "--ratio") grid.ratio = std::atof(next());
    else if (arg == "--scheme") grid.scheme = scheme_from_name(next());
    else {
      std::fprintf(stderr, "unknown argument %s\n", arg.c_str());
      return 2;
    }
  }
  if (as.empty())
    for (int i = 0; i <= 9; ++i) as.push_back(1.0 - 0.05 * i);
  AggregationModel base;
  base.size = size;
  base.truncation = Truncation::cutoff;
  base.initial = monodisperse(1);
  base.grid = grid;
  std::printf("cutoff, monodisperse, grid %s, Brent tolerance %g, convergence %g, N <= %zu; load average at start %s\n",
              grid.describe().c_str(), options.relative_tolerance, options.convergence,
              options.effective_max_size(grid), load_average().c_str());
  std::printf("| a | lambda_crit | N | classes | lambda_crit(N/2) | change N/2 -> N | change 2K | change (r-1)/2 | bracket | omega | period | evaluations | wall s | CPU s | note |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  const auto started = std::chrono::steady_clock::now();
  const std::clock_t cpu_started = std::clock();
  const aggkit::bench::Figures figures("lambda_crit_curve", argc, argv);
  // Graded grids are other cases than the uniform one (bench/check compares a case with its standing row).
  std::string grid_case;
  if (!grid.uniform()) {
    grid_case = " K=" + std::to_string(grid.resolved) + " r=" + aggkit::bench::Figures::text(grid.ratio);
    if (grid.scheme != GridScheme::four_moment) grid_case += std::string(" ") + scheme_name(grid.scheme);
  }
  hopf_curve(base, as, guess, size, options, [&](const ConvergedHopfPoint& p) {
    std::printf("| %.2f | %.6g | %zu | %zu | %.6g | %.2e | %.2e | %.2e | %.1e | %.5g | %.4g | %d | %.1f | %.1f | %s%s |\n", p.a,
                p.lambda_crit, p.size, p.unknowns, p.lambda_crit_half, p.change, p.change_K, p.change_ratio, p.bracket,
                p.omega, p.omega > 0 ? 2 * M_PI / p.omega : NAN, p.evaluations, p.seconds, p.cpu_seconds,
                p.converged ? "" : "NOT CONVERGED: ", p.note.c_str());
    for (std::size_t i = 0; i < p.by_size.size(); ++i)
      std::printf("|   | N = %zu: %s | %d evaluations, %.1f s CPU | %s |\n", p.sizes[i],
                  p.by_size[i].found ? aggkit::bench::Figures::text(p.by_size[i].lambda_crit).c_str() : "not found",
                  p.by_size[i].evaluations, p.by_size[i].cpu_seconds, p.by_size[i].note.c_str());
    std::fflush(stdout);
    const std::string case_name = "a=" + aggkit::bench::Figures::text(p.a) + grid_case;
    figures.add(case_name, "lambda_crit", p.converged ? p.lambda_crit : NAN, "1");
    figures.add(case_name, "change_2N", p.converged ? p.change : NAN, "1");
    figures.add(case_name, "N", double(p.size), "1");
    if (!grid.uniform()) {
      figures.add(case_name, "change_2K", p.converged ? p.change_K : NAN, "1");
      figures.add(case_name, "change_half_ratio", p.converged ? p.change_ratio : NAN, "1");
    }
    figures.add(case_name, "cpu_seconds", p.cpu_seconds, "s");
  });
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double cpu = double(std::clock() - cpu_started) / CLOCKS_PER_SEC;
  std::printf("total %.1f s wall, %.1f s CPU; load average at end %s\n", total, cpu, load_average().c_str());
  const std::string curve_case = std::to_string(as.size()) + " a" + grid_case;
  figures.add(curve_case, "wall_seconds", total, "s");
  figures.add(curve_case, "cpu_seconds", cpu, "s");
}
