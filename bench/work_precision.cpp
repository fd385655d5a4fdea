// Work-precision study of the CVODE integrators for the aggregation-shattering equations (the two cases
// whose finite-difference run times [Kalinov2022, Tables 3–4] reports):
// run time against the error of M0, M2, M3 at t = 1, 10, 100 relative to a tight-tolerance reference,
// for each integrator option, plus the direct O(N^2) right-hand side as baseline in the same run.
//   bench_work_precision [a|b] [--quick]
//   (a) constant kernel, λ = 0.1, N = 32768;  (b) ballistic kernel, λ = 0.01, N = 5000.
#include <chrono>
#include <optional>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/moments.hpp"
#include "bench/figures.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/rates.hpp"

using namespace aggkit;

namespace {

const std::vector<double> times{1.0, 10.0, 100.0};
const std::vector<double> orders{0.0, 2.0, 3.0};
std::optional<aggkit::bench::Figures> figures;  // set in main
std::string study_case;                         // "case=a", set by study()

struct Run {
  std::vector<std::vector<double>> moments;  // [time][order]
  IntegratorStatistics stats;
  bool failed = false;
  std::string failure;
  double reached = 0.0;
};

Run run(const AggregationModel& model, const IntegratorOptions& options, double until = 100.0) {
  Run r;
  std::vector<double> outputs;
  for (double t : times)
    if (t <= until) outputs.push_back(t);
  try {
    r.stats = integrate(model, outputs, options, [&](double t, std::span<const double> n, double) {
      r.moments.push_back(moments(n, orders));
      r.reached = t;
    });
  } catch (const std::exception& e) {
    r.failed = true;
    r.failure = e.what();
  }
  return r;
}

double max_error(const Run& r, const Run& reference) {
  double worst = 0.0;
  for (std::size_t i = 0; i < r.moments.size(); ++i)
    for (std::size_t q = 0; q < orders.size(); ++q)
      worst = std::max(worst, relative_error(r.moments[i][q], reference.moments[i][q]));
  return worst;
}

void print_row(const char* label, double rtol, const Run& r, const Run& reference) {
  if (r.failed) {
    figures->add(study_case + " integrator=" + label + " rtol=" + aggkit::bench::Figures::text(rtol), "max_relative_error",
                 std::nan(""), "1");
    std::printf("| %-22s | %7.0e | failed at t = %g: %.60s |\n", label, rtol, r.reached, r.failure.c_str());
    return;
  }
  std::printf("| %-22s | %7.0e | %8.3f | %7ld | %7ld | %7ld | %9.2e |", label, rtol, r.stats.wall_seconds,
              r.stats.steps, r.stats.rhs_evaluations, r.stats.linear_iterations, max_error(r, reference));
  for (std::size_t i = 0; i < r.moments.size(); ++i) {
    double e = 0.0;
    for (std::size_t q = 0; q < orders.size(); ++q) e = std::max(e, relative_error(r.moments[i][q], reference.moments[i][q]));
    std::printf(" %8.1e", e);
  }
  std::printf(" |\n");
  std::fflush(stdout);
  const std::string case_name = study_case + " integrator=" + label + " rtol=" + aggkit::bench::Figures::text(rtol);
  figures->add(case_name, "wall_seconds", r.stats.wall_seconds, "s");
  figures->add(case_name, "max_relative_error", max_error(r, reference), "1");
}

void study(const char* name, AggregationModel model, bool quick) {
  study_case = std::string("case=") + name;
  std::printf("\n### Case (%s): %s, lambda = %s, N = %zu, monodisperse, t = 1, 10, 100\n\n", name,
              model.kernel.describe().c_str(), model.lambda.describe().c_str(), model.size);
  IntegratorOptions reference_options;
  reference_options.rtol = 1e-12;
  reference_options.atol = 1e-16;
  reference_options.atol_exponent = 3.0;
  reference_options.lowrank_tolerance = 1e-12;
  reference_options.project_mass = false;  // slows CVODE at atol 1e-16 (see IntegratorOptions)
  const Run reference = run(model, reference_options);
  if (reference.failed) throw std::runtime_error("reference failed: " + reference.failure);
  // Self-check of the reference against one at rtol 1e-11.
  IntegratorOptions check_options = reference_options;
  check_options.rtol = 1e-11;
  const Run check = run(model, check_options);
  std::printf("Reference: bdf-gmres, fast RHS, rtol 1e-12, atol 1e-16/k^3, low-rank tolerance 1e-12, no projection: %.2f s,"
              " %ld steps, kernel rank %zu (max relative entry error %.1e); it differs from rtol 1e-11 by %.1e.\n",
              reference.stats.wall_seconds, reference.stats.steps, reference.stats.kernel_rank,
              reference.stats.kernel_relative_error, max_error(check, reference));
  std::printf("Reference moments at t = 100: M0 = %.12e, M2 = %.12e, M3 = %.12e\n\n", reference.moments[2][0],
              reference.moments[2][1], reference.moments[2][2]);
  std::printf("| integrator (atol = rtol/100 /k^3) | rtol | time [s] | steps | RHS | lin. it. | max rel. err | err t=1 | t=10 | t=100 |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  const std::vector<double> rtols = quick ? std::vector<double>{1e-6, 1e-8} : std::vector<double>{1e-5, 1e-6, 1e-7, 1e-8, 1e-9};
  struct Variant {
    const char* label;
    IntegratorMethod method;
    Preconditioner preconditioner;
    RatesPath rates;
  };
  const std::vector<Variant> variants{
      {"bdf-gmres + monomer", IntegratorMethod::bdf_gmres, Preconditioner::monomer, RatesPath::fast},
      {"bdf-gmres + Jacobi", IntegratorMethod::bdf_gmres, Preconditioner::jacobi, RatesPath::fast},
      {"bdf-gmres, no prec.", IntegratorMethod::bdf_gmres, Preconditioner::none, RatesPath::fast},
      {"adams (fixed point)", IntegratorMethod::adams, Preconditioner::none, RatesPath::fast},
      {"erk (dormand-prince-5)", IntegratorMethod::erk, Preconditioner::none, RatesPath::fast},
      {"auto", IntegratorMethod::automatic, Preconditioner::monomer, RatesPath::fast}};
  for (const auto& v : variants)
    for (double rtol : rtols) {
      IntegratorOptions o;
      o.method = v.method;
      o.preconditioner = v.preconditioner;
      o.rates = v.rates;
      o.rtol = rtol;
      o.atol = rtol * 1e-2;
      o.atol_exponent = 3.0;
      o.max_steps = v.method == IntegratorMethod::adams || v.method == IntegratorMethod::erk ? 20000 : 200000;
      print_row(v.label, rtol, run(model, o), reference);
    }
  // Baseline: the direct O(N^2) right-hand side (the test oracle) with the same integrator and
  // tolerances, in the same run. One direct J·v costs two O(N^2) bilinear evaluations, so the full
  // run to t = 100 would take many minutes: it is run to t = 1 for N ≤ 10^4, and the per-evaluation
  // costs below give the rest (at N = 32768 one direct J·v takes seconds, so only those are measured).
  if (model.size <= 10000) {
    IntegratorOptions direct;
    direct.rates = RatesPath::direct;
    direct.rtol = 1e-7;
    const Run baseline = run(model, direct, 1.0);
    IntegratorOptions fast = direct;
    fast.rates = RatesPath::fast;
    const Run same = run(model, fast, 1.0);
    std::printf("\nDirect-RHS baseline (defaults but rtol 1e-7) to t = 1: direct %.3f s (%ld RHS, %ld J.v),"
                " fast %.3f s (%ld RHS, %ld J.v): speed-up %.1fx; moments differ by %.1e.\n",
                baseline.stats.wall_seconds, baseline.stats.rhs_evaluations, baseline.stats.jacobian_vector_products,
                same.stats.wall_seconds, same.stats.rhs_evaluations, same.stats.jacobian_vector_products,
                baseline.stats.wall_seconds / same.stats.wall_seconds, max_error(baseline, same));
    figures->add(study_case + " rtol=1e-7 t=1", "speedup_over_direct_rhs", baseline.stats.wall_seconds / same.stats.wall_seconds, "1");
  }
  // Per-evaluation cost on a developed distribution (the reference state at t = 100 is not stored;
  // a smooth power law with cutoff stands in for it).
  std::vector<double> n(model.size), f(model.size), v(model.size), jv(model.size);
  for (std::size_t k = 1; k <= model.size; ++k)
    n[k - 1] = 0.1 * std::pow(double(k), -1.5) * std::exp(-double(k) / 1000.0), v[k - 1] = std::sin(double(k));
  std::printf("\nPer-evaluation cost (n_k = 0.1 k^-1.5 e^{-k/1000}):");
  for (RatesPath path : {RatesPath::direct, RatesPath::fast}) {
    auto rates = make_rates(model, path, 1e-10, 1e-4);
    const int reps = path == RatesPath::direct ? (model.size > 10000 ? 1 : 3) : 100;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) n[0] *= 1.0 + 1e-9, rates->evaluate(0.0, n, f);
    const auto t1 = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) rates->jacobian_times(0.0, n, v, jv);
    const auto t2 = std::chrono::steady_clock::now();
    std::printf("\n%s RHS: %.3f ms per evaluation, %.3f ms per J.v", to_string(path).c_str(),
                std::chrono::duration<double, std::milli>(t1 - t0).count() / reps,
                std::chrono::duration<double, std::milli>(t2 - t1).count() / reps);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string which = "ab";
  figures.emplace("work_precision", argc, argv);
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    else which = argv[i];
  }
  AggregationModel a;
  a.kernel = Kernel::constant();
  a.lambda = ShatteringRate::constant(0.1);
  a.size = 32768;
  a.initial = monodisperse(a.size);
  AggregationModel b = a;
  b.kernel = Kernel::ballistic();
  b.lambda = ShatteringRate::constant(0.01);
  b.size = 5000;
  b.initial = monodisperse(b.size);
  if (which.find('a') != std::string::npos) study("a", a, quick);
  if (which.find('b') != std::string::npos) study("b", b, quick);
  return 0;
}
