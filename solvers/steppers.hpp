#pragma once
// The time steppers integrate() can use (internal to the solvers library), each started from y0 (n and
// the leaked mass) at t0.
#include <memory>

#include "solvers/integration_problem.hpp"

namespace aggkit::integration {

// CVODE: BDF (GMRES or dense Newton) or Adams, as options.method says (`auto` gets BDF with GMRES).
std::unique_ptr<TimeStepper> make_cvode_stepper(Problem& problem, const IntegratorOptions& options,
                                                SUNContext context, N_Vector y0, double t0);
// ARKODE's explicit Runge–Kutta with options.erk_table.
std::unique_ptr<TimeStepper> make_erk_stepper(Problem& problem, const IntegratorOptions& options,
                                              SUNContext context, N_Vector y0, double t0);
// Explicit Runge–Kutta while the steps are bounded by accuracy, BDF with GMRES from the first stretch
// where they are bounded by stability (solvers/auto_stepper.cpp).
std::unique_ptr<TimeStepper> make_auto_stepper(Problem& problem, const IntegratorOptions& options,
                                               SUNContext context, N_Vector y0, double t0);

}  // namespace aggkit::integration
