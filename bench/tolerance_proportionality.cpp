// Tolerance proportionality at N = 32768 for every integrator: K_ij = 2 (brownian, a = 0), monodisperse
// start, relative errors of M0, M2, M3 at t = 1, 10, 100 for rtol = 1e-6 … 1e-10 (atol = rtol/100 · k^-3).
//   λ = 0, drop:     exact M0 = 1/(1+t), M2 = 1+2t, M3 = 1+6t+6t² [Leyvraz2003, Sec. 2];
//   λ = 0.1, cutoff: exact M0 = N*/(1 + (N*-1) e^{-2λt}), N* = 2λ/(1+2λ) (derivation in
//                    tests/solvers/test_tolerance_proportionality.cpp); M2, M3 against a reference run at
//                    rtol 1e-12 (atol 1e-16 k^-3, no projection).
// bdf-dense is limited to small N: it runs at N = 512, against the exact moments (λ = 0) or the logistic
// M0 (λ = 0.1) at t = 1, 10. A truncation check prints the λ = 0.1 moments at
// N = 512 … 32768 (rtol 1e-10), so that the unit test's smaller N can be judged.
//   bench_tolerance_proportionality [--quick]   (--quick: rtol 1e-6, 1e-8, 1e-10 only)
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "solvers/exact_solutions.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {

AggregationModel constant_two(double lambda, std::size_t N, Truncation truncation) {
  AggregationModel model;
  model.kernel = Kernel::brownian(0.0);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = N;
  model.truncation = truncation;
  model.initial = monodisperse(N);
  return model;
}

const std::vector<double> orders{0.0, 2.0, 3.0};

struct Run {
  std::vector<double> times;
  std::vector<std::vector<double>> moments;  // [output][order]
  IntegratorStatistics stats;
};

Run run(const AggregationModel& model, const std::vector<double>& times, const IntegratorOptions& options) {
  Run r;
  r.times = times;
  r.stats = integrate(model, times, options,
                      [&](double, std::span<const double> n, double) { r.moments.push_back(moments(n, orders)); });
  return r;
}

// Reference values [output][order]; NaN where none is known (then the entry is not compared).
using Reference = std::vector<std::vector<double>>;

Reference exact_reference(double lambda, const std::vector<double>& times, const Run* tight) {
  Reference ref;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    if (lambda == 0.0)
      ref.push_back({1.0 / (1.0 + t), 1.0 + 2.0 * t, 1.0 + 6.0 * t + 6.0 * t * t});
    else
      ref.push_back({exact_total_density_k2(lambda, t), tight ? tight->moments[i][1] : NAN, tight ? tight->moments[i][2] : NAN});
  }
  return ref;
}

std::optional<aggkit::bench::Figures> figures;  // set in main
std::string study_case;                         // "lambda=0.1 N=32768 cutoff", set by study()

void print_row(const char* label, double rtol, const Run& r, const Reference& ref) {
  double worst = 0.0;
  std::vector<double> per_time;
  for (std::size_t i = 0; i < r.moments.size(); ++i) {
    double e = 0.0;
    for (std::size_t q = 0; q < orders.size(); ++q)
      if (!std::isnan(ref[i][q])) e = std::max(e, relative_error(r.moments[i][q], ref[i][q]));
    per_time.push_back(e);
    worst = std::max(worst, e);
  }
  std::printf("| %-20s | %7.0e | %7.2f | %6ld | %9.2e | %6.3f |", label, rtol, r.stats.wall_seconds, r.stats.steps, worst,
              worst / rtol);
  for (double e : per_time) std::printf(" %8.1e |", e);
  std::printf("\n");
  std::fflush(stdout);
  const std::string case_name = study_case + " integrator=" + label + " rtol=" + aggkit::bench::Figures::text(rtol);
  figures->add(case_name, "error_over_rtol", worst / rtol, "1");
  figures->add(case_name, "wall_seconds", r.stats.wall_seconds, "s");
}

struct Variant {
  const char* label;
  IntegratorMethod method;
  Preconditioner preconditioner;
};

void study(double lambda, Truncation truncation, std::size_t N, const std::vector<double>& rtols) {
  const std::vector<double> times{1.0, 10.0, 100.0};
  const AggregationModel model = constant_two(lambda, N, truncation);
  Run tight;
  bool have_tight = false;
  study_case = "lambda=" + aggkit::bench::Figures::text(lambda) + " N=" + std::to_string(N) + " " + to_string(truncation);
  std::printf("\n### K = 2, lambda = %g, N = %zu, %s, monodisperse\n\n", lambda, N, to_string(truncation).c_str());
  if (lambda > 0.0) {
    IntegratorOptions o;
    o.rtol = 1e-12;
    o.atol = 1e-16;
    o.project_mass = false;
    tight = run(model, times, o);
    have_tight = true;
    std::printf("M2, M3 reference: bdf-gmres rtol 1e-12, atol 1e-16 k^-3, no projection (%.1f s, %ld steps); its M0 is off"
                " the closed form by %.1e, %.1e, %.1e at t = 1, 10, 100.\n\n",
                tight.stats.wall_seconds, tight.stats.steps, relative_error(tight.moments[0][0], exact_total_density_k2(lambda, 1.0)),
                relative_error(tight.moments[1][0], exact_total_density_k2(lambda, 10.0)),
                relative_error(tight.moments[2][0], exact_total_density_k2(lambda, 100.0)));
  }
  const Reference ref = exact_reference(lambda, times, have_tight ? &tight : nullptr);
  std::printf("| integrator | rtol | time [s] | steps | max rel. err | err/rtol | t=1 | t=10 | t=100 |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  const std::vector<Variant> variants{
      {"bdf-gmres + monomer", IntegratorMethod::bdf_gmres, Preconditioner::monomer},
      {"bdf-gmres + Jacobi", IntegratorMethod::bdf_gmres, Preconditioner::jacobi},
      {"bdf-gmres, no prec.", IntegratorMethod::bdf_gmres, Preconditioner::none},
      {"adams (fixed point)", IntegratorMethod::adams, Preconditioner::none}};
  for (const auto& v : variants)
    for (double rtol : rtols) {
      IntegratorOptions o;
      o.method = v.method;
      o.preconditioner = v.preconditioner;
      o.rtol = rtol;
      o.max_steps = 200000;
      print_row(v.label, rtol, run(model, times, o), ref);
    }
  // bdf-dense at N = 512 to t = 10 only: at t = 100 the truncation is not negligible at N = 512 (λ = 0:
  // the exact tail (100/101)^512 = e^{-5}; λ = 0.1: M0 off the closed form by 3.7e-4, truncation check).
  const std::vector<double> dense_times{1.0, 10.0};
  const AggregationModel small = constant_two(lambda, 512, truncation);
  const Reference dense_ref = exact_reference(lambda, dense_times, nullptr);
  for (double rtol : rtols) {
    IntegratorOptions o;
    o.method = IntegratorMethod::bdf_dense;
    o.rtol = rtol;
    print_row("bdf-dense (N = 512)", rtol, run(small, dense_times, o), dense_ref);
  }
}

}  // namespace

int main(int argc, char** argv) {
  figures.emplace("tolerance_proportionality", argc, argv);
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const std::vector<double> rtols =
      quick ? std::vector<double>{1e-6, 1e-8, 1e-10} : std::vector<double>{1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  std::printf("Errors: largest relative error over M0, M2, M3 (λ = 0: exact; λ = 0.1: M0 exact, M2 and M3 against the"
              " reference) per output time; max rel. err over all outputs.\n");
  study(0.0, Truncation::drop, 32768, rtols);
  study(0.1, Truncation::cutoff, 32768, rtols);
  // Truncation check for the λ = 0.1 unit test (N = 8192) and the dense rows (N = 512).
  std::printf("\nTruncation check, lambda = 0.1, cutoff, rtol 1e-10 (bdf-gmres): moments at t = 100\n\n");
  std::printf("| N | M0 | M2 | M3 | M0 rel. err vs closed form |\n|---|---|---|---|---|\n");
  for (std::size_t N : {512, 1024, 4096, 8192, 32768}) {
    IntegratorOptions o;
    o.rtol = 1e-10;
    const Run r = run(constant_two(0.1, N, Truncation::cutoff), {100.0}, o);
    std::printf("| %zu | %.12e | %.12e | %.12e | %.1e |\n", N, r.moments[0][0], r.moments[0][1], r.moments[0][2],
                relative_error(r.moments[0][0], exact_total_density_k2(0.1, 100.0)));
  }
  return 0;
}
