// The `auto` method: explicit Runge–Kutta while its steps are bounded by accuracy, BDF with GMRES from the
// first stretch where they are bounded by stability — the switch of LSODA [Petzold1983], one way. The
// explicit step h is stable for h ρ ≤ β (β the method's real stability boundary, ρ the spectral radius,
// here the largest loss rate |J_kk|); when the step the controller asks for stays at h ρ ≥ `stiff` β over
// `checks` checks (one every `every` steps) the stretch is stiff, and BDF, whose step stability does not
// bound, takes over from the state reached. Aggregation with shattering runs into a steady state whose
// fastest loss rates only grow with the distribution, so there is no switch back.
#include <memory>

#include "solvers/erk_stepper.hpp"

namespace aggkit::integration {

namespace {

constexpr double stiff = 0.5;  // h ρ / β above which a check counts as stability-bound
constexpr int every = 8;       // steps between checks (a check costs about one right-hand side)
constexpr int checks = 3;      // consecutive stability-bound checks before BDF takes over

class AutoStepper final : public TimeStepper {
 public:
  AutoStepper(Problem& problem, const IntegratorOptions& options, SUNContext context, N_Vector y0, double t0)
      : problem_(problem), options_(options), context_(context),
        erk_(std::make_unique<ErkStepper>(problem, options, context, y0, t0)) {}

  void advance(double t_out, N_Vector out) override {
    while (!bdf_ && erk_->time() < t_out) {
      erk_->step(t_out);
      if (++steps_ % every != 0) continue;
      bound_ = erk_->stiffness() >= stiff ? bound_ + 1 : 0;
      if (bound_ >= checks) {
        switch_time_ = erk_->time();
        bdf_ = make_cvode_stepper(problem_, options_, context_, erk_->state(), switch_time_);
      }
    }
    if (bdf_) bdf_->advance(t_out, out);
    else erk_->advance(t_out, out);
  }

  void add_statistics(IntegratorStatistics& stats) const override {
    erk_->add_statistics(stats);
    if (bdf_) bdf_->add_statistics(stats);
    stats.stiff_from = switch_time_;
  }

 private:
  Problem& problem_;
  const IntegratorOptions& options_;
  SUNContext context_;
  std::unique_ptr<ErkStepper> erk_;
  std::unique_ptr<TimeStepper> bdf_;
  long steps_ = 0;
  int bound_ = 0;
  double switch_time_ = -1.0;
};

}  // namespace

std::unique_ptr<TimeStepper> make_auto_stepper(Problem& problem, const IntegratorOptions& options,
                                               SUNContext context, N_Vector y0, double t0) {
  return std::make_unique<AutoStepper>(problem, options, context, y0, t0);
}

}  // namespace aggkit::integration
