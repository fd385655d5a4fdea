// CVODE [Hindmarsh2005, Gardner2022] as a time stepper of the aggregation-shattering system: BDF with
// matrix-free GMRES or a dense Jacobian, or Adams with fixed-point iteration; every BDF step projected
// onto the conserved mass (integration_problem.hpp).
#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "solvers/steppers.hpp"

namespace aggkit::integration {

namespace {

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

int project_mass(sunrealtype, N_Vector y, N_Vector correction, sunrealtype, N_Vector error, void* data) {
  project_onto_mass_shell(*static_cast<Problem*>(data), N_VGetArrayPointer(y), N_VGetArrayPointer(correction),
                          error ? N_VGetArrayPointer(error) : nullptr);
  return 0;
}

class CvodeStepper final : public TimeStepper {
 public:
  CvodeStepper(Problem& problem, const IntegratorOptions& options, SUNContext context, N_Vector y0, double t0)
      : problem_(problem), options_(options), t_(t0) {
    y_ = N_VClone(y0);
    N_VScale(1.0, y0, y_);
    mem_ = CVodeCreate(options.method == IntegratorMethod::adams ? CV_ADAMS : CV_BDF, context);
    if (!mem_) throw std::runtime_error("CVodeCreate failed");
    call(CVodeSetErrHandlerFn(mem_, error_handler, &problem), "CVodeSetErrHandlerFn");
    call(CVodeInit(mem_, rhs, t0, y_), "CVodeInit");
    call(CVodeSetUserData(mem_, &problem), "CVodeSetUserData");
    call(CVodeWFtolerances(mem_, error_weights), "CVodeWFtolerances");
    if (options.method != IntegratorMethod::adams && options.stability_limit_detection)
      call(CVodeSetStabLimDet(mem_, SUNTRUE), "CVodeSetStabLimDet");
    attach_solvers(context);
    // CVODE projects BDF steps only; Adams runs get their outputs projected.
    if (options.project_mass && options.method != IntegratorMethod::adams && options.effective_atol() >= 1e-10)
      call(CVodeSetProjFn(mem_, project_mass), "CVodeSetProjFn");
  }
  ~CvodeStepper() override {
    CVodeFree(&mem_);
    if (linear_) SUNLinSolFree(linear_);
    if (nonlinear_) SUNNonlinSolFree(nonlinear_);
    if (matrix_) SUNMatDestroy(matrix_);
    N_VDestroy(y_);
  }

  void advance(double t_out, N_Vector out) override {
    while (t_ < t_out) {
      // One internal step at a time (for progress); CVodeSetMaxNumSteps counts per call, so the step
      // limit is enforced here.
      long taken = 0;
      CVodeGetNumSteps(mem_, &taken);
      if (taken >= options_.max_steps)
        throw StepLimitReached("CVODE: reached max_steps = " + std::to_string(options_.max_steps) +
                                 " at t = " + std::to_string(t_) + " before t = " + std::to_string(t_out));
      const int flag = CVode(mem_, t_out, y_, &t_, CV_ONE_STEP);
      call(flag, "CVode (t = " + std::to_string(t_) + ")");
      if (options_.progress) options_.progress(std::min(t_, t_out));
      if (options_.on_step) options_.on_step(t_, std::span<const double>(N_VGetArrayPointer(y_), problem_.N));
    }
    call(CVodeGetDky(mem_, t_out, 0, out), "CVodeGetDky");
  }

  void add_statistics(IntegratorStatistics& stats) const override {
    long v = 0;
    CVodeGetNumSteps(mem_, &v), stats.steps += v;
    CVodeGetNumRhsEvals(mem_, &v), stats.rhs_evaluations += v;
    CVodeGetNumErrTestFails(mem_, &v), stats.error_test_failures += v;
    CVodeGetNumNonlinSolvConvFails(mem_, &v), stats.nonlinear_failures += v;
    if (options_.method == IntegratorMethod::adams) return;
    CVodeGetNumLinIters(mem_, &v), stats.linear_iterations += v;
    CVodeGetNumJacEvals(mem_, &v), stats.jacobian_evaluations += v;
    CVodeGetNumLinConvFails(mem_, &v), stats.linear_convergence_failures += v;
    CVodeGetNumJtimesEvals(mem_, &v), stats.jacobian_vector_products += v;
    CVodeGetNumPrecEvals(mem_, &v), stats.preconditioner_setups += v;
    CVodeGetNumPrecSolves(mem_, &v), stats.preconditioner_solves += v;
  }

 private:
  void call(int flag, const std::string& what) const { check(flag, "CVODE: " + what, problem_); }

  void attach_solvers(SUNContext context) {
    switch (options_.method) {
      case IntegratorMethod::bdf_dense:
        matrix_ = SUNDenseMatrix(sunindextype(problem_.N + 1), sunindextype(problem_.N + 1), context);
        linear_ = SUNLinSol_Dense(y_, matrix_, context);
        call(CVodeSetLinearSolver(mem_, linear_, matrix_), "CVodeSetLinearSolver");
        call(CVodeSetJacFn(mem_, dense_jacobian_callback), "CVodeSetJacFn");
        return;
      case IntegratorMethod::adams:
        nonlinear_ = SUNNonlinSol_FixedPoint(y_, 0, context);
        call(CVodeSetNonlinearSolver(mem_, nonlinear_), "CVodeSetNonlinearSolver");
        return;
      default: {  // bdf-gmres (also what `auto` hands a stiff stretch to)
        const bool preconditioned = options_.preconditioner != Preconditioner::none;
        linear_ = SUNLinSol_SPGMR(y_, preconditioned ? SUN_PREC_LEFT : SUN_PREC_NONE, options_.krylov_dimension, context);
        call(CVodeSetLinearSolver(mem_, linear_, nullptr), "CVodeSetLinearSolver");
        call(CVodeSetJacTimes(mem_, nullptr, jtimes), "CVodeSetJacTimes");
        call(CVodeSetEpsLin(mem_, options_.linear_tolerance_factor), "CVodeSetEpsLin");
        if (preconditioned)
          call(CVodeSetPreconditioner(mem_, preconditioner_setup, preconditioner_solve), "CVodeSetPreconditioner");
      }
    }
  }

  Problem& problem_;
  const IntegratorOptions& options_;
  void* mem_ = nullptr;
  N_Vector y_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver linear_ = nullptr;
  SUNNonlinearSolver nonlinear_ = nullptr;
  double t_ = 0.0;
};

}  // namespace

std::unique_ptr<TimeStepper> make_cvode_stepper(Problem& problem, const IntegratorOptions& options,
                                                SUNContext context, N_Vector y0, double t0) {
  return std::make_unique<CvodeStepper>(problem, options, context, y0, t0);
}

}  // namespace aggkit::integration
