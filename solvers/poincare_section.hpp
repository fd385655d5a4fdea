#pragma once
// The Poincaré section M0 = level, crossed upwards, read at CVODE's internal steps (IntegratorOptions::on_step):
// the crossing time where the cubic through two steps either side meets the level, and optionally the state
// there, the same cubic through the four steps' states. The solution between BDF steps is a polynomial of the
// step's order, so the cubic's error is that of the fourth derivative, while a straight line's (the second)
// moved the periods of a smooth cycle by ~1e-5 of a period from one return to the next (brownian a = 0.95,
// λ = 0.01, rtol 1e-8, graded K = 32). Far below the Hopf curve a burst lasts ~1e-4 of a period, and only the
// steps resolve it.
#include <cstddef>
#include <deque>
#include <span>
#include <vector>

namespace aggkit {

class UpwardCrossings {
 public:
  // keep_states: also interpolate the state at each crossing (four states of the model's length are kept).
  UpwardCrossings(double level, bool keep_states = false) : level_(level), keep_states_(keep_states) {}

  // One internal step at time t with densities n (M0 = Σ n). True where a crossing became known: the one
  // between the two steps before this one (its cubic needs this step), or, at the very start, a crossing between
  // the first two steps (a straight line). time() and state() then describe it.
  bool add(double t, std::span<const double> n);

  double time() const { return time_; }
  const std::vector<double>& state() const { return state_; }  // empty unless keep_states

 private:
  void interpolate(std::size_t low, std::size_t high);  // the crossing between samples low and high

  double level_;
  bool keep_states_;
  std::deque<double> t_, m0_;                 // the latest steps (at most 4)
  std::deque<std::vector<double>> n_;         // and their states (keep_states)
  bool pending_ = false;                      // a crossing between the two steps before the latest
  double time_ = 0.0;
  std::vector<double> state_;
};

}  // namespace aggkit
