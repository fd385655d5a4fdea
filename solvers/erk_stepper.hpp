#pragma once
// Explicit Runge–Kutta stepping with ARKODE's ERKStep (solvers/erk_stepper.cpp). Internal to the solvers
// library; `auto` (solvers/auto_stepper.cpp) drives it step by step and reads its stiffness.
#include <memory>

#include "solvers/steppers.hpp"

namespace aggkit::integration {

// β: the explicit method is stable for h ρ ≤ β on the negative real axis (ρ the spectral radius).
double real_stability_boundary(ErkTable table);

class ErkStepper final : public TimeStepper {
 public:
  ErkStepper(Problem& problem, const IntegratorOptions& options, SUNContext context, N_Vector y0, double t0);
  ~ErkStepper() override;
  ErkStepper(const ErkStepper&) = delete;
  ErkStepper& operator=(const ErkStepper&) = delete;

  void advance(double t_out, N_Vector out) override;
  void add_statistics(IntegratorStatistics& stats) const override;

  // One internal step towards t_out (never past it); returns the time reached.
  double step(double t_out);
  double time() const { return t_; }
  N_Vector state() const { return y_; }
  // h ρ / β for the next step: near 1 when the step is bounded by stability rather than accuracy.
  double stiffness();

 private:
  void call(int flag, const std::string& what) const;

  Problem& problem_;
  const IntegratorOptions& options_;
  void* mem_ = nullptr;
  N_Vector y_ = nullptr;
  double t_ = 0.0, stop_ = -1.0;
  double boundary_ = 0.0;
};

}  // namespace aggkit::integration
