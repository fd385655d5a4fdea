// CVODE driver for the aggregation-shattering system. The state is y = (n_1, ..., n_N, L), L the mass
// leaked through the truncation (dL/dt = leak rate; 0 under cutoff), so that Σ k n_k + L = M is an
// exact linear invariant of the system, onto which every step (and every output) is projected.
#include "solvers/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"

namespace aggkit {

IntegratorMethod integrator_method_from_name(const std::string& name) {
  if (name == "bdf-gmres") return IntegratorMethod::bdf_gmres;
  if (name == "bdf-dense") return IntegratorMethod::bdf_dense;
  if (name == "adams") return IntegratorMethod::adams;
  throw InputError("method", "\"" + name + "\"", "one of bdf-gmres, bdf-dense, adams");
}

std::string to_string(IntegratorMethod m) {
  switch (m) {
    case IntegratorMethod::bdf_gmres: return "bdf-gmres";
    case IntegratorMethod::bdf_dense: return "bdf-dense";
    case IntegratorMethod::adams: return "adams";
  }
  return "?";
}

Preconditioner preconditioner_from_name(const std::string& name) {
  if (name == "monomer") return Preconditioner::monomer;
  if (name == "jacobi") return Preconditioner::jacobi;
  if (name == "none") return Preconditioner::none;
  throw InputError("preconditioner", "\"" + name + "\"", "one of monomer, jacobi, none");
}

std::string to_string(Preconditioner p) {
  return p == Preconditioner::monomer ? "monomer" : p == Preconditioner::jacobi ? "jacobi" : "none";
}

double IntegratorOptions::effective_lowrank_tolerance() const {
  return lowrank_tolerance > 0.0 ? lowrank_tolerance : std::max(1e-12, std::min(1e-8, 1e-3 * rtol));
}

void IntegratorOptions::validate() const { integrator_option_rows().check(*this); }

namespace {

// Everything the C callbacks need; exceptions are parked here and rethrown after CVODE returns.
struct Problem {
  const Discretisation* grid = nullptr;
  Rates* rates = nullptr;
  std::size_t N = 0;
  std::vector<double> sizes;              // the classes' sizes (pivots; 1..N on the uniform grid)
  Rates::MonomerCoupling coupling;        // preconditioner: the O(N)-invertible part of J
  std::vector<double> inverse;            // 1/(1 - γ J_kk)
  double gamma = 0.0;
  bool monomer_preconditioner = true;     // false: Jacobi (diagonal only)
  std::vector<double> dense;              // row-major dense Jacobian buffer
  double rtol = 0.0, mass = 0.0;          // for the mass projection
  const double* abstol = nullptr;
  std::exception_ptr error;
  std::string cvode_message;
};

std::span<const double> view(N_Vector v, std::size_t N) { return {N_VGetArrayPointer(v), N}; }
std::span<double> view_mut(N_Vector v, std::size_t N) { return {N_VGetArrayPointer(v), N}; }

template <class F>
int guarded(Problem* p, F&& f) {
  try {
    f();
    return 0;
  } catch (...) {
    p->error = std::current_exception();
    return -1;  // unrecoverable: CVODE stops and we rethrow
  }
}

int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* data) {
  auto* p = static_cast<Problem*>(data);
  return guarded(p, [&] {
    p->rates->evaluate(t, view(y, p->N), view_mut(ydot, p->N));
    N_VGetArrayPointer(ydot)[p->N] = p->rates->leak_rate(t, view(y, p->N));
  });
}

int jtimes(N_Vector v, N_Vector Jv, sunrealtype t, N_Vector y, N_Vector, void* data, N_Vector) {
  auto* p = static_cast<Problem*>(data);
  return guarded(p, [&] {
    p->rates->jacobian_times(t, view(y, p->N), view(v, p->N), view_mut(Jv, p->N));
    // The leaked mass does not feed back into n, so its row of J may be left out (Newton then
    // converges for L as soon as it has for n); computing it would cost two O(N R) sums per J·v.
    N_VGetArrayPointer(Jv)[p->N] = 0.0;
  });
}

// Preconditioner P = I - γ (D + S + C): D the diagonal of J, S its subdiagonal and C its monomer
// column (monomer attachment, the most frequent collisions, couples k to k-1 and to 1). P is lower
// triangular, so P z = r is solved by forward substitution in O(N).
int preconditioner_setup(sunrealtype t, N_Vector y, N_Vector, sunbooleantype jok, sunbooleantype* jcur,
                         sunrealtype gamma, void* data) {
  auto* p = static_cast<Problem*>(data);
  return guarded(p, [&] {
    if (!jok || p->coupling.diagonal.empty()) {
      p->rates->jacobian_monomer_coupling(t, view(y, p->N), p->coupling);
      if (!p->monomer_preconditioner) {
        std::fill(p->coupling.subdiagonal.begin(), p->coupling.subdiagonal.end(), 0.0);
        std::fill(p->coupling.monomer_column.begin(), p->coupling.monomer_column.end(), 0.0);
      }
      *jcur = SUNTRUE;
    } else {
      *jcur = SUNFALSE;
    }
    p->gamma = gamma;
    p->inverse.resize(p->N);
    for (std::size_t k = 0; k < p->N; ++k) p->inverse[k] = 1.0 / (1.0 - gamma * p->coupling.diagonal[k]);
  });
}

int preconditioner_solve(sunrealtype, N_Vector, N_Vector, N_Vector r, N_Vector z, sunrealtype, sunrealtype,
                         int, void* data) {
  auto* p = static_cast<Problem*>(data);
  const double* rr = N_VGetArrayPointer(r);
  double* zz = N_VGetArrayPointer(z);
  const auto& S = p->coupling.subdiagonal;
  const auto& C = p->coupling.monomer_column;
  const double g = p->gamma;
  zz[0] = rr[0] * p->inverse[0];
  for (std::size_t k = 1; k < p->N; ++k)
    zz[k] = (rr[k] + g * (C[k] * zz[0] + S[k] * zz[k - 1])) * p->inverse[k];
  zz[p->N] = rr[p->N];  // the leaked mass: its row (∂leak/∂n) is left out
  return 0;
}

int dense_jacobian_callback(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector,
                            N_Vector) {
  auto* p = static_cast<Problem*>(data);
  return guarded(p, [&] {
    const std::size_t N = p->N;
    p->dense.resize(N * N);
    p->grid->dense_jacobian(t, view(y, N), p->dense);
    SUNMatZero(J);
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t j = 0; j < N; ++j) SM_ELEMENT_D(J, sunindextype(i), sunindextype(j)) = p->dense[i * N + j];
    p->dense.resize(N);
    p->grid->leak_gradient(t, view(y, N), p->dense);
    for (std::size_t j = 0; j < N; ++j) SM_ELEMENT_D(J, sunindextype(N), sunindextype(j)) = p->dense[j];
  });
}

// Projection onto the mass shell g·y = Σ k n_k + L = M. The defect d = g·y - M is removed by
// δ_i = -d w_i g_i / Σ_j w_j g_j² with w_i = S_i²/g_i^4 (S_i = rtol|y_i| + atol_i the error scale) on the
// components in the relative-tolerance regime (rtol|y_i| ≥ atol_i) and w_i = 0 on all others. Like the
// orthogonal projection in the error-weight metric it moves only what may move, and the extra 1/g^4
// keeps the correction on small sizes, where it changes M2 and M3 least. L is not corrected.
//
// Why the sizes below their absolute tolerance are left alone: they hold no information at the
// tolerance, but a correction there, however small (~1e-40 at rtol 1e-8), turns the exact zeros beyond
// the distribution's natural support into a tail spanning all N sizes. The fast right-hand side reads
// its active range and the decay rate of its tilted convolution off that tail (solvers/rates_fast.cpp),
// so the tilt collapses (θ ≈ ln(1e41)/N) and FFT round-off of ~1e-16 e^{-θ s} lands on sizes s ~ 10^3,
// below their tolerance floor, where CVODE accepts it. Weighted by k³ over thousands of sizes that junk
// shifted M3 by ~1e-6 at early times whatever rtol (constant kernel, N = 32768: 1.6e-6 … 7.4e-6 at
// rtol 1e-5 … 1e-8; bench/log/cvode-tolerance-proportionality.md). Restricted to the relative regime, the correction stays on the
// resolved sizes, the tail keeps its exact zeros, and the errors fall with rtol (tests/solvers/
// test_tolerance_proportionality.cpp). The defect itself is the Newton residual of the mass, so the
// resolved sizes absorb it at O(rtol) relative change.
void project_onto_mass_shell(const Problem& p, const double* y, double* correction, double* error) {
  const std::size_t size = p.N + 1;
  auto g = [&](std::size_t i) { return i < p.N ? p.sizes[i] : 1.0; };
  double mass = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < size; ++i) {
    // L itself is never corrected: it stays the integral of the leak rate (0 under cutoff).
    const double relative = p.rtol * std::abs(y[i]);
    const double scale = i == p.N || relative < p.abstol[i] ? 0.0 : relative + p.abstol[i];
    correction[i] = scale * scale / (g(i) * g(i) * g(i));  // w_i g_i
    mass += g(i) * y[i];
    norm += g(i) * correction[i];
  }
  if (!(norm > 0.0)) {  // nothing resolved (all sizes below their absolute tolerance): leave y as it is
    std::fill(correction, correction + size, 0.0);
    return;
  }
  if (error) {  // the local error estimate is projected the same way
    double error_mass = 0.0;
    for (std::size_t i = 0; i < size; ++i) error_mass += g(i) * error[i];
    for (std::size_t i = 0; i < size; ++i) error[i] -= correction[i] * error_mass / norm;
  }
  const double excess = (mass - p.mass) / norm;
  for (std::size_t i = 0; i < size; ++i) correction[i] *= -excess;
}

int project_mass(sunrealtype, N_Vector y, N_Vector correction, sunrealtype, N_Vector error, void* data) {
  project_onto_mass_shell(*static_cast<Problem*>(data), N_VGetArrayPointer(y), N_VGetArrayPointer(correction),
                          error ? N_VGetArrayPointer(error) : nullptr);
  return 0;
}

// Error weights. CVODE's error norm is a root mean square over all N+1 components, so when most sizes
// are far-tail entries below their absolute tolerance the errors of the few sizes that matter are
// diluted by sqrt(N / active): at N = 2^17 the steady-state M0 was off by 2e-4 at rtol 1e-6. The
// weights 1/(rtol|y_i| + atol_i) are therefore scaled by sqrt((N+1)/A), A the number of components in
// the relative-tolerance regime (rtol|y_i| ≥ atol_i), which makes the norm an RMS over those.
int error_weights(N_Vector y, N_Vector weights, void* data) {
  auto* p = static_cast<Problem*>(data);
  const double* yy = N_VGetArrayPointer(y);
  double* w = N_VGetArrayPointer(weights);
  const std::size_t size = p->N + 1;
  std::size_t active = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const double relative = p->rtol * std::abs(yy[i]);
    if (relative >= p->abstol[i]) ++active;
    w[i] = 1.0 / (relative + p->abstol[i]);
  }
  const double scale = std::sqrt(double(size) / double(std::max<std::size_t>(active, 1)));
  for (std::size_t i = 0; i < size; ++i) w[i] *= scale;
  return 0;
}

void error_handler(int code, const char* module, const char* function, char* message, void* data) {
  auto* p = static_cast<Problem*>(data);
  p->cvode_message = std::string(module) + "/" + function + " (" + std::to_string(code) + "): " + message;
}

// Owns the SUNDIALS objects of one integration.
struct Session {
  SUNContext context = nullptr;
  N_Vector y = nullptr, abstol = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear = nullptr;
  SUNNonlinearSolver nonlinear = nullptr;
  void* cvode = nullptr;
  ~Session() {
    if (cvode) CVodeFree(&cvode);
    if (linear) SUNLinSolFree(linear);
    if (nonlinear) SUNNonlinSolFree(nonlinear);
    if (matrix) SUNMatDestroy(matrix);
    if (abstol) N_VDestroy(abstol);
    if (y) N_VDestroy(y);
    if (context) SUNContext_Free(&context);
  }
};

void check(int flag, const char* call, const Problem& problem) {
  if (flag < 0) {
    if (problem.error) std::rethrow_exception(problem.error);
    throw std::runtime_error(std::string("CVODE: ") + call + " failed with flag " + std::to_string(flag) +
                             (problem.cvode_message.empty() ? "" : ": " + problem.cvode_message));
  }
}

}  // namespace

IntegratorStatistics integrate(const AggregationModel& model, std::span<const double> output_times,
                               const IntegratorOptions& options, const OutputCallback& on_output,
                               const IntegratorRestart* restart) {
  options.validate();
  const double t_end = output_times.empty() ? 0.0 : output_times.back();
  model.validate(t_end);
  for (std::size_t i = 0; i < output_times.size(); ++i)
    if (!std::isfinite(output_times[i]) || output_times[i] < 0.0 || (i > 0 && !(output_times[i] > output_times[i - 1])))
      throw InputError("output_times[" + std::to_string(i) + "]", format_value(output_times[i]),
                       "output times must be finite, >= 0 and strictly increasing");
  const std::unique_ptr<Discretisation> grid = make_discretisation(model);
  const std::size_t N = grid->unknowns();  // N on the uniform grid, the graded grid's classes otherwise
  if (options.method == IntegratorMethod::bdf_dense && N > options.dense_limit)
    throw InputError("method", "\"bdf-dense\"",
                     "a dense Jacobian is limited to N <= " + std::to_string(options.dense_limit) +
                         " (N = " + std::to_string(N) + "); use bdf-gmres");

  const auto started = std::chrono::steady_clock::now();
  auto rates = grid->rates(options.rates, options.effective_lowrank_tolerance(), options.jacobian_tolerance);
  Problem problem;
  problem.grid = grid.get();
  problem.rates = rates.get();
  problem.N = N;
  problem.sizes = grid->sizes();

  Session s;
  if (SUNContext_Create(nullptr, &s.context) != 0) throw std::runtime_error("SUNContext_Create failed");
  s.y = N_VNew_Serial(sunindextype(N + 1), s.context);  // n_1..n_N and the leaked mass
  s.abstol = N_VNew_Serial(sunindextype(N + 1), s.context);
  double* y = N_VGetArrayPointer(s.y);
  double* abstol = N_VGetArrayPointer(s.abstol);
  double density_scale = 0.0;
  const std::vector<double> initial = grid->initial_state();
  for (std::size_t k = 0; k < N; ++k) {
    y[k] = initial[k];
    density_scale = std::max(density_scale, y[k]);
    problem.mass += problem.sizes[k] * y[k];
  }
  for (std::size_t k = 0; k < N; ++k)
    abstol[k] = std::max(options.effective_atol() * std::pow(problem.sizes[k], -options.atol_exponent),
                         options.effective_atol_floor() * density_scale);
  y[N] = 0.0;
  const double t0 = restart ? restart->time : 0.0;
  if (restart) {  // the tolerances and the mass above stay those of the start
    if (restart->densities.size() != N || !(t0 >= 0.0) || !std::isfinite(t0))
      throw InputError("restart", std::to_string(restart->densities.size()) + " densities at t = " + format_value(t0),
                       std::to_string(N) + " densities at a time >= 0");
    std::copy(restart->densities.begin(), restart->densities.end(), y);
    y[N] = restart->leaked_mass;
  }
  if (options.negligible_fraction > 0.0) {  // the adaptive active range: ν_k = fraction · atol_k
    std::vector<double> levels(N);
    for (std::size_t k = 0; k < N; ++k) levels[k] = options.negligible_fraction * abstol[k];
    rates->set_negligible_levels(std::move(levels));
  }
  // The leaked mass matters relative to the total mass M; an absolute tolerance tied to atol would make
  // CVODE resolve a leak of ~1e-20 driven by the far tail (thousands of extra steps were seen).
  abstol[N] = std::max(options.effective_atol(), options.rtol * problem.mass);
  IntegratorStatistics stats;
  stats.atol_floor = options.effective_atol_floor() * density_scale;
  problem.rtol = options.rtol;
  problem.monomer_preconditioner = options.preconditioner == Preconditioner::monomer;
  problem.abstol = abstol;

  s.cvode = CVodeCreate(options.method == IntegratorMethod::adams ? CV_ADAMS : CV_BDF, s.context);
  if (!s.cvode) throw std::runtime_error("CVodeCreate failed");
  check(CVodeSetErrHandlerFn(s.cvode, error_handler, &problem), "CVodeSetErrHandlerFn", problem);
  check(CVodeInit(s.cvode, rhs, t0, s.y), "CVodeInit", problem);
  check(CVodeSetUserData(s.cvode, &problem), "CVodeSetUserData", problem);
  check(CVodeWFtolerances(s.cvode, error_weights), "CVodeWFtolerances", problem);

  switch (options.method) {
    case IntegratorMethod::bdf_gmres:
      s.linear = SUNLinSol_SPGMR(s.y, options.preconditioner != Preconditioner::none ? SUN_PREC_LEFT : SUN_PREC_NONE,
                                 options.krylov_dimension, s.context);
      check(CVodeSetLinearSolver(s.cvode, s.linear, nullptr), "CVodeSetLinearSolver", problem);
      check(CVodeSetJacTimes(s.cvode, nullptr, jtimes), "CVodeSetJacTimes", problem);
      check(CVodeSetEpsLin(s.cvode, options.linear_tolerance_factor), "CVodeSetEpsLin", problem);
      if (options.preconditioner != Preconditioner::none)
        check(CVodeSetPreconditioner(s.cvode, preconditioner_setup, preconditioner_solve),
              "CVodeSetPreconditioner", problem);
      break;
    case IntegratorMethod::bdf_dense:
      s.matrix = SUNDenseMatrix(sunindextype(N + 1), sunindextype(N + 1), s.context);
      s.linear = SUNLinSol_Dense(s.y, s.matrix, s.context);
      check(CVodeSetLinearSolver(s.cvode, s.linear, s.matrix), "CVodeSetLinearSolver", problem);
      check(CVodeSetJacFn(s.cvode, dense_jacobian_callback), "CVodeSetJacFn", problem);
      break;
    case IntegratorMethod::adams:
      s.nonlinear = SUNNonlinSol_FixedPoint(s.y, 0, s.context);
      check(CVodeSetNonlinearSolver(s.cvode, s.nonlinear), "CVodeSetNonlinearSolver", problem);
      break;
  }

  // CVODE projects BDF steps only; Adams runs get their outputs projected.
  if (options.project_mass && options.method != IntegratorMethod::adams && options.effective_atol() >= 1e-10)
    check(CVodeSetProjFn(s.cvode, project_mass), "CVodeSetProjFn", problem);
  std::vector<double> correction(N + 1);

  N_Vector out = N_VClone(s.y);
  struct Free {
    N_Vector v;
    ~Free() { N_VDestroy(v); }
  } free_out{out};
  double t = t0;
  for (double t_out : output_times) {
    if (restart && t_out <= t0) continue;
    if (t_out == 0.0) {
      on_output(0.0, view(s.y, N), 0.0);
      continue;
    }
    while (t < t_out) {
      // One internal step at a time (for progress); CVodeSetMaxNumSteps counts per call, so the step
      // limit is enforced here.
      long taken = 0;
      CVodeGetNumSteps(s.cvode, &taken);
      if (taken >= options.max_steps)
        throw std::runtime_error("CVODE: reached max_steps = " + std::to_string(options.max_steps) +
                                 " at t = " + std::to_string(t) + " before t = " + std::to_string(t_out));
      const int flag = CVode(s.cvode, t_out, s.y, &t, CV_ONE_STEP);
      check(flag, ("CVode (t = " + std::to_string(t) + ")").c_str(), problem);
      if (options.progress) options.progress(std::min(t, t_out));
    }
    check(CVodeGetDky(s.cvode, t_out, 0, out), "CVodeGetDky", problem);
    double* interpolated = N_VGetArrayPointer(out);
    if (options.project_mass) {  // the interpolant between steps is not on the mass shell
      project_onto_mass_shell(problem, interpolated, correction.data(), nullptr);
      for (std::size_t i = 0; i <= N; ++i) interpolated[i] += correction[i];
    }
    const auto n = view(out, N);
    std::size_t negatives = 0, beyond = 0;
    for (std::size_t k = 0; k < N; ++k) {
      const double x = n[k];
      if (!(x < 0.0)) continue;
      ++negatives, stats.most_negative_density = std::min(stats.most_negative_density, x);
      if (x < -abstol[k]) {
        ++beyond;
        if (x < stats.most_negative_beyond_tolerance)
          stats.most_negative_beyond_tolerance = x, stats.most_negative_size = std::size_t(problem.sizes[k]), stats.most_negative_time = t_out;
      }
    }
    stats.negative_densities = std::max(stats.negative_densities, negatives);
    stats.negative_beyond_tolerance = std::max(stats.negative_beyond_tolerance, beyond);
    on_output(t_out, n, interpolated[N]);
  }

  long v = 0;
  CVodeGetNumSteps(s.cvode, &v), stats.steps = v;
  CVodeGetNumRhsEvals(s.cvode, &v), stats.rhs_evaluations = v;
  CVodeGetNumErrTestFails(s.cvode, &v), stats.error_test_failures = v;
  CVodeGetNumNonlinSolvConvFails(s.cvode, &v), stats.nonlinear_failures = v;
  if (options.method != IntegratorMethod::adams) {
    CVodeGetNumLinIters(s.cvode, &v), stats.linear_iterations = v;
    CVodeGetNumJacEvals(s.cvode, &v), stats.jacobian_evaluations = v;
    CVodeGetNumLinConvFails(s.cvode, &v), stats.linear_convergence_failures = v;
    CVodeGetNumJtimesEvals(s.cvode, &v), stats.jacobian_vector_products = v;
    CVodeGetNumPrecEvals(s.cvode, &v), stats.preconditioner_setups = v;
    CVodeGetNumPrecSolves(s.cvode, &v), stats.preconditioner_solves = v;
  }
  stats.kernel_rank = rates->kernel_rank();
  stats.kernel_relative_error = rates->kernel_relative_error();
  const Rates::ActiveRangeStatistics range = rates->active_range_statistics();
  stats.active_size_final = range.final_size;
  stats.active_size_mean = range.mean_size;
  stats.fft_work_fraction = range.fft_work_fraction;
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return stats;
}

}  // namespace aggkit
