#pragma once
// What the time steppers of the aggregation-shattering system share (solvers/cvode_integrator.cpp drives
// them): the state y = (n_1, ..., n_N, L), L the mass leaked through the truncation, its tolerances, the
// right-hand side and error weights as SUNDIALS callbacks, and the projection onto the conserved mass.
// Internal to the solvers library.
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <exception>
#include <span>
#include <string>
#include <vector>

#include "solvers/cvode_integrator.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/model.hpp"
#include "solvers/rates.hpp"

namespace aggkit::integration {

// Everything the C callbacks need; exceptions are parked here and rethrown after SUNDIALS returns.
struct Problem {
  const Discretisation* grid = nullptr;   // the size classes: dense Jacobian and leak gradient
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
  std::string solver_message;
};

inline std::span<const double> view(N_Vector v, std::size_t N) { return {N_VGetArrayPointer(v), N}; }
inline std::span<double> view_mut(N_Vector v, std::size_t N) { return {N_VGetArrayPointer(v), N}; }

// Runs f, parking an exception in the problem; returns SUNDIALS' 0 (success) or -1 (unrecoverable).
template <class F>
int guarded(Problem* p, F&& f) {
  try {
    f();
    return 0;
  } catch (...) {
    p->error = std::current_exception();
    return -1;
  }
}

// f(t, y) with the leak rate as the last component (CVODE's and ARKODE's right-hand-side signature).
int rhs(double t, N_Vector y, N_Vector ydot, void* problem);
// Error weights 1/(rtol|y_i| + atol_i), scaled to an RMS over the resolved components (see the .cpp).
int error_weights(N_Vector y, N_Vector weights, void* problem);
// The correction that puts y on the mass shell Σ k n_k + L = M (and the same projection of `error`, if given).
void project_onto_mass_shell(const Problem& p, const double* y, double* correction, double* error);
// SUNDIALS' error handler: keeps the message for the exception thrown after a failed call.
void error_handler(int code, const char* module, const char* function, char* message, void* problem);
// Throws for a negative SUNDIALS flag: the parked exception, or std::runtime_error naming the call.
void check(int flag, const std::string& call, const Problem& problem);

// One time-stepping method over the problem, started from y at t0.
class TimeStepper {
 public:
  virtual ~TimeStepper() = default;
  // Steps to t_out (options.progress after every internal step, the step limit enforced) and writes
  // y(t_out) into `out`.
  virtual void advance(double t_out, N_Vector out) = 0;
  // Adds its counters (steps, right-hand sides, ...) to `stats`.
  virtual void add_statistics(IntegratorStatistics& stats) const = 0;
};

// The SUNDIALS context of one integration.
struct Context {
  SUNContext context = nullptr;
  Context();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

}  // namespace aggkit::integration
