// The low-rank factorisation of a kernel without an exact one (solvers/low_rank.hpp): CPU seconds of
// Kernel::separable_form at size N and tolerance tol, the rank, the error the factorisation reports and
// the number of entries behind it, and an independent measurement here: the max relative error against
// direct evaluation on every entry of 40 full rows (sizes 1..8, N, and log-spaced and pseudo-random rows)
// and on 10^6 pseudo-random entries, the corners (small i, large j) included.
//   bench_kernel_factorisation [N ...] [--kernel ballistic|ballistic2d] [--tol T]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "solvers/kernels.hpp"
#include "solvers/low_rank.hpp"

using namespace aggkit;

namespace {
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

double independent_error(const Kernel& kernel, const SeparableForm& form, std::size_t N) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 1; i <= std::min<std::size_t>(8, N); ++i) rows.push_back(i);
  rows.push_back(N);
  std::mt19937_64 random(12345);
  for (int r = 0; r < 16; ++r) rows.push_back(std::size_t(std::exp(std::log(double(N)) * (r + 0.5) / 16.0)));
  for (int r = 0; r < 15; ++r) rows.push_back(1 + random() % N);
  double worst = 0.0;
  const std::size_t R = form.rank();
  std::vector<double> row(N);
  for (std::size_t i : rows) {
    std::fill(row.begin(), row.end(), 0.0);
    for (std::size_t p = 0; p < R; ++p)
      for (std::size_t q = 0; q < R; ++q)
        if (form.coupling[p][q] != 0.0) {
          const double w = form.coupling[p][q] * form.features[p][i - 1];
          for (std::size_t j = 0; j < N; ++j) row[j] += w * form.features[q][j];
        }
    for (std::size_t j = 1; j <= N; ++j) worst = std::max(worst, std::abs(row[j - 1] / kernel(i, j) - 1.0));
  }
  for (int e = 0; e < 1000000; ++e) {
    const std::size_t i = 1 + random() % N, j = 1 + random() % N;
    worst = std::max(worst, std::abs(separable_entry(form, i, j) / kernel(i, j) - 1.0));
  }
  return worst;
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  std::string name = "ballistic";
  double tol = 1e-12;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--kernel" && i + 1 < argc) name = argv[++i];
    else if (arg == "--tol" && i + 1 < argc) tol = std::atof(argv[++i]);
    else sizes.push_back(std::strtoul(arg.c_str(), nullptr, 10));
  }
  if (sizes.empty()) sizes = {5000, 1u << 17};
  const Kernel kernel = Kernel::from_name(name, {});
  const aggkit::bench::Figures figures("kernel_factorisation", argc, argv);
  std::printf("| kernel | N | tol | CPU s | rank | reported error | checked entries | independent error |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t N : sizes) {
    const double started = cpu_seconds();
    const SeparableForm form = kernel.separable_form(N, tol);
    const double seconds = cpu_seconds() - started;
    const double error = independent_error(kernel, form, N);
    std::printf("| %s | %zu | %g | %.3f | %zu | %.2e | %zu | %.2e |\n", name.c_str(), N, tol, seconds, form.rank(),
                form.max_relative_error, form.checked_entries, error);
    std::fflush(stdout);
    const std::string case_name = name + " N=" + std::to_string(N) + " tol=" + aggkit::bench::Figures::text(tol);
    figures.add(case_name, "cpu_seconds", seconds, "s");
    figures.add(case_name, "rank", double(form.rank()), "1");
    figures.add(case_name, "relative_error", error, "1");
  }
}
