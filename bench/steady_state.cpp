// Steady states by SNES Newton–Krylov [Balay2022]: N = 2^14 and 2^17, ballistic and brownian kernels,
// λ = 0.01 and 0.1, cutoff truncation (mass conserved exactly), monodisperse unit mass. For each case:
// wall time (CVODE start included), the CVODE start time, Newton and GMRES iterations, the final
// relative residual ||F|| / ||F(n(0))|| and M0 of the steady state.
// The parts: setup (the size-N system: kernel factorisation) and start (CVODE, or the coarse-to-fine
// start's solve at N/4) in wall seconds; Newton is the rest. "CPU s" is the process's CPU time for the
// whole solve (std::clock): on the shared machine it is the figure that does not grow with the load, and
// on an idle machine the serial solve's wall time is about it.
//   bench_steady_state [N ...] [--kernel NAME[:a]] [--lambda L] [--noprec] [--start T] [--no-coarse]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "solvers/steady_state.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  std::vector<Kernel> kernels;
  std::vector<double> lambdas;
  SteadyStateOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--kernel" && i + 1 < argc) {
      const std::string name = argv[++i];
      kernels.push_back(name == "ballistic" ? Kernel::ballistic() : Kernel::brownian(std::atof(name.c_str() + 10)));
    } else if (arg == "--lambda" && i + 1 < argc) {
      lambdas.push_back(std::atof(argv[++i]));
    } else if (arg == "--noprec") {
      options.precondition = false;
    } else if (arg == "--coarse-above" && i + 1 < argc) {
      options.coarse_start_above = std::strtoul(argv[++i], nullptr, 10);
    } else if (arg == "--no-coarse") {
      options.coarse_start_above = 0;
    } else if (arg == "--start" && i + 1 < argc) {
      options.start_time = std::atof(argv[++i]);
    } else {
      sizes.push_back(std::strtoul(arg.c_str(), nullptr, 10));
    }
  }
  if (sizes.empty()) sizes = {1u << 14, 1u << 17};
  if (kernels.empty()) kernels = {Kernel::ballistic(), Kernel::brownian(0.5)};
  if (lambdas.empty()) lambdas = {0.01, 0.1};
  const aggkit::bench::Figures figures("steady_state", argc, argv);
  std::printf("| kernel | λ | N | seconds | CPU s | setup s | start s | coarse N | CVODE start t | Newton | GMRES | relative residual | M0 | leak | note |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t N : sizes)
    for (const Kernel& kernel : kernels)
      for (double lambda : lambdas) {
        AggregationModel model;
        model.kernel = kernel;
        model.lambda = ShatteringRate::constant(lambda);
        model.size = N;
        model.truncation = Truncation::cutoff;
        model.initial = monodisperse(N);
        const std::clock_t cpu_started = std::clock();
        const SteadyStateResult r = solve_steady_state(model, options);
        const double cpu = double(std::clock() - cpu_started) / CLOCKS_PER_SEC;
        std::printf("| %s | %g | %zu | %.2f | %.2f | %.2f | %.2f | %zu | %g | %d | %ld | %.1e | %.6g | %.1e | %s |\n",
                    kernel.describe().c_str(), lambda, N, r.seconds, cpu, r.setup_seconds, r.start_seconds, r.coarse_size,
                    r.start_time, r.newton_iterations, r.krylov_iterations, r.relative_residual,
                    moment(r.n, 0.0), r.leak_rate, (r.converged ? "converged " + r.note : r.note).c_str());
        if (const char* dump = std::getenv("DUMP")) {  // the steady state, one n_k a line
          if (FILE* f = std::fopen(dump, "w")) {
            for (double x : r.n) std::fprintf(f, "%.17g\n", x);
            std::fclose(f);
          }
        }
        const std::string case_name = kernel.describe() + " lambda=" + aggkit::bench::Figures::text(lambda) +
                                      " N=" + std::to_string(N);
        figures.add(case_name, "wall_seconds", r.converged ? r.seconds : std::nan(""), "s");
        figures.add(case_name, "cpu_seconds", r.converged ? cpu : std::nan(""), "s");
        figures.add(case_name, "relative_residual", r.relative_residual, "1");
        if (std::getenv("VERBOSE")) {
          for (double h : r.residual_history) std::printf(" %.1e", h);
          std::printf("\n");
        }
        std::fflush(stdout);
      }
}
