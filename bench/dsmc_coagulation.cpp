// DSMC speed on pure coagulation and on the constant kernel with shattering:
//  (1) constant kernel K = 1, λ = 0, 10^6 particles, to t = 50 (number density falls 26×): run time,
//      accepted events per second, relative Euclidean error of the size distribution against the exact
//      n_k = 4/(t+2)^2 (t/(t+2))^{k-1} [Leyvraz2003], and of M0, M2;
//  (2) constant kernel, λ = 0.1, 10^6 particles to t = 1, 10, 100 ([Kalinov2022, Tables 1 and 3]):
//      run time and the Euclidean error of the size distribution against a CVODE reference.
//   bench_dsmc_coagulation [particles] [method ar|fast] [bucket]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "particle/dsmc/simulation.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/exact_solutions.hpp"

using namespace aggkit;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// sqrt(Σ (n_k - ref_k)^2 / Σ ref_k^2) over the sizes of the reference.
double distribution_error(const dsmc::Snapshot& s, const std::vector<double>& reference) {
  double error = 0.0, norm = 0.0;
  for (std::size_t k = 1; k <= reference.size(); ++k) {
    const double d = s.density(k) - reference[k - 1];
    error += d * d;
    norm += reference[k - 1] * reference[k - 1];
  }
  return std::sqrt(error / norm);
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t particles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  dsmc::Options options;
  options.particles = particles;
  if (argc > 2) options.method = dsmc::method_from_name(argv[2]);
  if (argc > 3) options.bucket = std::strtoull(argv[3], nullptr, 10);
  const aggkit::bench::Figures figures("dsmc_coagulation", argc, argv);
  const std::string case_name = "particles=" + std::to_string(particles) + " method=" + dsmc::to_string(options.method);
  std::printf("particles %llu, method %s, bucket %llu\n", (unsigned long long)particles,
              dsmc::to_string(options.method).c_str(), (unsigned long long)options.bucket);

  {  // (1) pure coagulation
    AggregationModel model;
    model.size = 4096;
    model.initial = monodisperse(model.size);
    const double t_end = 50.0;
    const auto start = std::chrono::steady_clock::now();
    dsmc::Simulation simulation(model, options, 1, t_end);
    simulation.advance_to(t_end);
    const double wall = seconds_since(start);
    const auto s = simulation.snapshot();
    const auto& st = simulation.statistics();
    std::vector<double> exact = exact_distribution("constant", model.size, t_end);
    std::printf("(1) constant, lambda 0, t = 50: %.3f s, %llu accepted events (%llu trials), %.3g events/s, "
                "doublings %llu\n", wall, (unsigned long long)st.accepted(), (unsigned long long)st.trials,
                double(st.accepted()) / wall, (unsigned long long)st.doublings);
    std::printf("    M0 %.6e (exact %.6e, rel. err %.2e), M2 rel. err %.2e, size-distribution error %.3e, "
                "mass conserved: %s\n", s.moment(0), exact_moment("constant", 0, t_end),
                std::abs(s.moment(0) / exact_moment("constant", 0, t_end) - 1),
                std::abs(s.moment(2) / exact_moment("constant", 2, t_end) - 1), distribution_error(s, exact),
                simulation.mass() == simulation.initial_mass() << st.doublings ? "yes" : "NO");
    figures.add(case_name + " lambda=0 t=50", "wall_seconds", wall, "s");
    figures.add(case_name + " lambda=0 t=50", "events_per_second", double(st.accepted()) / wall, "1/s");
    figures.add(case_name + " lambda=0 t=50", "distribution_error", distribution_error(s, exact), "1");
  }
  {  // (2) constant kernel with shattering, λ = 0.1
    AggregationModel model;
    model.size = 32768;
    model.lambda = ShatteringRate::constant(0.1);
    model.initial = monodisperse(model.size);
    const std::vector<double> times{1.0, 10.0, 100.0};
    std::vector<std::vector<double>> reference;
    IntegratorOptions tight;
    tight.rtol = 1e-9;
    tight.method = IntegratorMethod::adams;
    integrate(model, times, tight, [&](double, std::span<const double> n, double) { reference.emplace_back(n.begin(), n.end()); });
    const auto start = std::chrono::steady_clock::now();
    dsmc::Simulation simulation(model, options, 1, 100.0);
    for (std::size_t i = 0; i < times.size(); ++i) {
      simulation.advance_to(times[i]);
      const double wall = seconds_since(start);
      const auto s = simulation.snapshot();
      std::printf("(2) constant, lambda 0.1, t = %g: %.3f s, %llu accepted events, distribution error %.2e, "
                  "M0 rel. err %.2e\n", times[i], wall, (unsigned long long)simulation.statistics().accepted(),
                  distribution_error(s, reference[i]),
                  std::abs(s.moment(0) / aggkit::moment(reference[i], 0) - 1));
      const std::string at = case_name + " lambda=0.1 t=" + std::to_string(int(times[i]));
      figures.add(at, "distribution_error", distribution_error(s, reference[i]), "1");
      figures.add(at, "wall_seconds", wall, "s");
    }
  }
  return 0;
}
