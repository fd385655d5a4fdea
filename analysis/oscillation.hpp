#pragma once
// Classification of a uniformly sampled time series x(t) (e.g. M0(t) or M2(t) of an aggregation-shattering
// run) by its long-time behaviour: steady (constant within a tolerance), damped (relaxing, with the decay rate
// γ of its envelope e^{-γ t}), or sustained (an oscillation whose amplitude and period have converged).
//
// Method (on the tail of the series, the last `tail_fraction` of its time span):
//  1. the tail's half swing (max - min)/2 below `steady_tolerance` of its scale is steady;
//  2. otherwise its turning points are found with a prominence threshold (a maximum counts once the signal
//     has fallen `prominence` × half swing below it, and vice versa; small noise creates no cycles) and refined
//     by a parabola through the three samples around each (error O((Δt/T)^4) for a smooth signal);
//  3. the half differences of successive turning points are the cycle amplitudes A_j; a least-squares fit of
//     ln A_j against time (analysis/least_squares.hpp) gives the envelope decay rate γ (> 0 decaying, < 0
//     growing) and its standard error;
//     the spacing of turning points of the same kind gives the period;
//  4. relative envelope change γ·W over the fitted span W above `drift_tolerance`: damped; below
//     -drift_tolerance: sustained but still growing (unstable steady state, limit cycle not yet reached);
//     otherwise sustained, and converged when amplitude and period agree between the first and the second
//     half of the tail's cycles within `drift_tolerance` and `period_tolerance` over at least
//     `minimum_cycles` cycles;
//  5. no turning points: a monotone relaxation, damped with γ from a fit of ln|Δx| against time (for
//     x = x∞ + c e^{-γt} the increments decay at the same rate); converged only if the increments decay by
//     more than `drift_tolerance` over the tail (else a slow drift: damped, not converged, "run longer");
//  6. cycle lengths that scatter by more than `regularity_tolerance` (coefficient of variation): irregular
//     (noise or chaos, not a periodic or linearly damped mode).
#include <cstddef>
#include <limits>
#include <span>
#include <string>

namespace aggkit {

enum class Regime { steady, damped, sustained, irregular };
std::string to_string(Regime regime);

struct OscillationCriteria {
  // The transient is skipped: only the last half of the run is classified by default.
  double tail_fraction = 0.5;
  // Relative half swing (of max(|mean|, half swing)) below which the tail is constant. A CVODE run at
  // rtol 1e-6 carries relative errors of ~1e-6 per step and a global error a few times that; 1e-4 leaves a
  // factor ~100 over this noise while any oscillation a plot would show (≥ 0.01 %) is counted.
  double steady_tolerance = 1e-4;
  // Largest relative change of the envelope over the fitted span (|γ| W) for a sustained oscillation, and of
  // the mean amplitude between the halves of the tail for a converged one. 2 % is ~10x the scatter of
  // amplitudes measured on sampled signals (sampling Δt = T/30, noise of 1 %; tests/analysis) and ~20x the
  // drift of the converged a = 0.95, λ = 0.01 limit cycle over 1000 time units (0.1 %).
  double drift_tolerance = 0.02;
  // Largest relative change of the period between the halves of the tail for a converged oscillation.
  double period_tolerance = 0.02;
  // Largest coefficient of variation of the cycle lengths for a regular oscillation: a limit cycle or a
  // linearly damped mode has a fixed period; nonlinear transients vary it by a few per cent at most.
  double regularity_tolerance = 0.1;
  // Reversal, as a fraction of the tail's half swing, that confirms a turning point.
  double prominence = 0.1;
  // Cycles in the tail needed for a converged verdict (amplitude and period compared over two halves).
  std::size_t minimum_cycles = 4;
  void validate() const;  // throws InputError naming the criterion
};

struct OscillationClassification {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  Regime regime = Regime::steady;
  double mean = nan;                // of the tail
  double amplitude = nan;           // half peak-to-peak: over the last cycles (oscillating) or the tail
  double relative_amplitude = nan;  // amplitude / |mean|
  double period = nan;              // over the last cycles; NaN without cycles
  // Over every cycle of the tail (a noisy series, e.g. one DSMC run: the more cycles, the smaller the error):
  // the mean spacing of turning points of the same kind, and the mean half difference of successive ones.
  double mean_period = nan;
  double mean_amplitude = nan;
  // √2 × the standard deviation of x over whole cycles (first to last turning point of the first one's kind):
  // the amplitude of a sine of the same variance. Noise of variance σ² raises it only by ~σ²/(2A), while
  // it raises every sampled extreme, and with it the half peak-to-peak amplitude, by about σ.
  double rms_amplitude = nan;
  double decay_rate = nan;          // γ of the envelope e^{-γ t} (> 0 decays); NaN for steady
  double decay_rate_error = nan;    // its standard error from the fit
  double amplitude_change = nan;    // relative, between the first and second half of the tail's cycles
  double period_change = nan;
  std::size_t cycles = 0;           // complete cycles in the tail
  bool converged = false;           // the verdict's own convergence check passed
  std::string note;                 // why a verdict is tentative ("only 2 cycles ...", "growing ...")
};

// `t` increasing and uniformly spaced (relative deviation ≤ 1e-6 of the spacing), `x` finite, both of
// the same length, at least 16 samples in the tail; otherwise InputError (key "series").
OscillationClassification classify_oscillation(std::span<const double> t, std::span<const double> x,
                                               const OscillationCriteria& criteria = {});

}  // namespace aggkit
