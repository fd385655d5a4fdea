// Explicit Runge–Kutta stepping of the aggregation-shattering system with ARKODE's ERKStep
// [Reynolds2023, Gardner2022]: embedded pairs of order 5 (Dormand–Prince [DormandPrince1980]), 6 (Verner
// [Verner1978]) or 8 (Fehlberg [Fehlberg1968]) with ARKODE's error control under the same error weights as CVODE. No
// Newton iteration and no Jacobian: each step costs its stages' right-hand sides, which pays off while
// the step is limited by accuracy (tight tolerances, non-stiff stretches). Outputs are reached exactly
// (a stop time at each), not interpolated, so the high order is not lost to a lower-order interpolant.
#include "solvers/erk_stepper.hpp"

#include <arkode/arkode_butcher_erk.h>
#include <arkode/arkode_erkstep.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace aggkit::integration {

namespace {

ARKODE_ERKTableID table_id(ErkTable table) {
  switch (table) {
    case ErkTable::dormand_prince_5: return ARKODE_DORMAND_PRINCE_7_4_5;
    case ErkTable::verner_6: return ARKODE_VERNER_8_5_6;
    case ErkTable::fehlberg_8: return ARKODE_FEHLBERG_13_7_8;
  }
  return ARKODE_FEHLBERG_13_7_8;
}

}  // namespace

// The method's stability polynomial R(z) = 1 + z bᵀ(I - zA)⁻¹1 on the negative real axis: the first z < 0
// (searched in steps of 0.01) where |R(z)| > 1 gives β, the explicit step's bound h ρ ≤ β.
double real_stability_boundary(ErkTable table) {
  ARKodeButcherTable b = ARKodeButcherTable_LoadERK(table_id(table));
  if (!b) throw std::runtime_error("ARKODE: no Butcher table for the ERK method");
  std::vector<double> stage(std::size_t(b->stages));
  double boundary = 0.0;
  for (double z = -0.01; z > -50.0; z -= 0.01) {
    double growth = 1.0;
    for (int i = 0; i < b->stages; ++i) {  // stage_i = z (1 + Σ_{j<i} a_ij stage_j)
      double sum = 1.0;
      for (int j = 0; j < i; ++j) sum += b->A[i][j] * stage[std::size_t(j)];
      stage[std::size_t(i)] = z * sum;
      growth += b->b[i] * stage[std::size_t(i)];
    }
    if (std::abs(growth) > 1.0 + 1e-12) break;
    boundary = -z;
  }
  ARKodeButcherTable_Free(b);
  return boundary;
}

ErkStepper::ErkStepper(Problem& problem, const IntegratorOptions& options, SUNContext context, N_Vector y0, double t0)
    : problem_(problem), options_(options), t_(t0), boundary_(real_stability_boundary(options.erk_table)) {
  y_ = N_VClone(y0);
  N_VScale(1.0, y0, y_);
  mem_ = ERKStepCreate(rhs, t0, y_, context);
  if (!mem_) throw std::runtime_error("ERKStepCreate failed");
  call(ERKStepSetErrHandlerFn(mem_, error_handler, &problem), "ERKStepSetErrHandlerFn");
  call(ERKStepSetUserData(mem_, &problem), "ERKStepSetUserData");
  call(ERKStepWFtolerances(mem_, error_weights), "ERKStepWFtolerances");
  call(ERKStepSetTableNum(mem_, table_id(options.erk_table)), "ERKStepSetTableNum");
  call(ERKStepSetMaxNumSteps(mem_, -1), "ERKStepSetMaxNumSteps");  // the limit is enforced in step()
}

ErkStepper::~ErkStepper() {
  ERKStepFree(&mem_);
  N_VDestroy(y_);
}

void ErkStepper::call(int flag, const std::string& what) const { check(flag, "ARKODE: " + what, problem_); }

double ErkStepper::step(double t_out) {
  long taken = 0;
  ERKStepGetNumSteps(mem_, &taken);
  if (taken >= options_.max_steps)
    throw StepLimitReached("ARKODE: reached max_steps = " + std::to_string(options_.max_steps) + " at t = " +
                             std::to_string(t_) + " before t = " + std::to_string(t_out));
  if (stop_ != t_out) call(ERKStepSetStopTime(mem_, t_out), "ERKStepSetStopTime"), stop_ = t_out;
  call(ERKStepEvolve(mem_, t_out, y_, &t_, ARK_ONE_STEP), "ERKStepEvolve (t = " + std::to_string(t_) + ")");
  if (t_ >= t_out) t_ = t_out;  // the stop time is reached exactly
  if (options_.progress) options_.progress(t_);
  if (options_.on_step) options_.on_step(t_, std::span<const double>(N_VGetArrayPointer(y_), problem_.N));
  return t_;
}

void ErkStepper::advance(double t_out, N_Vector out) {
  while (t_ < t_out) step(t_out);
  N_VScale(1.0, y_, out);
}

// h ρ / β with h the step the controller proposes next and ρ = max_k |J_kk| over the sizes present: the
// loss rates (1+λ) c_k, which dominate J's spectrum (gains couple a size only to larger ones, so J is
// close to triangular and its eigenvalues close to its diagonal).
double ErkStepper::stiffness() {
  double h = 0.0;
  ERKStepGetCurrentStep(mem_, &h);
  problem_.rates->jacobian_monomer_coupling(t_, view(y_, problem_.N), problem_.coupling);
  const double* y = N_VGetArrayPointer(y_);
  double rho = 0.0;
  for (std::size_t k = 0; k < problem_.N; ++k)
    if (y[k] != 0.0) rho = std::max(rho, std::abs(problem_.coupling.diagonal[k]));
  return std::abs(h) * rho / boundary_;
}

void ErkStepper::add_statistics(IntegratorStatistics& stats) const {
  long v = 0;
  ERKStepGetNumSteps(mem_, &v), stats.steps += v;
  ERKStepGetNumRhsEvals(mem_, &v), stats.rhs_evaluations += v;
  ERKStepGetNumErrTestFails(mem_, &v), stats.error_test_failures += v;
}

std::unique_ptr<TimeStepper> make_erk_stepper(Problem& problem, const IntegratorOptions& options, SUNContext context,
                                              N_Vector y0, double t0) {
  return std::make_unique<ErkStepper>(problem, options, context, y0, t0);
}

}  // namespace aggkit::integration
