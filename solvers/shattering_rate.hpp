#pragma once
// Shattering rate λ(t): constant, linear in t, or piecewise linear through tabulated points
// ([Kalinov2022, Sec. 5.2, Fig. 3b] uses λ(t) = 0.01 (1 - t/400) to drive a damped oscillation into a
// sustained one).
#include <functional>
#include <string>
#include <vector>

namespace aggkit {

class ShatteringRate {
 public:
  ShatteringRate() = default;  // λ = 0: pure aggregation
  static ShatteringRate constant(double lambda);
  static ShatteringRate linear(double initial, double slope);  // λ(t) = initial + slope t
  static ShatteringRate table(std::vector<double> times, std::vector<double> values);  // held flat outside
  // Any function of t (research code, e.g. a Python callable); `name` describes it. validate() samples it.
  static ShatteringRate function(std::function<double(double)> lambda, std::string name);

  double operator()(double t) const;  // never negative
  bool is_constant() const { return !function_ && times_.size() == 1; }
  bool is_zero() const { return is_constant() && values_[0] == 0.0; }
  // Throws InputError (key `key`) unless λ(t) is finite and >= 0 on [0, t_end].
  void validate(double t_end, const std::string& key = "lambda") const;
  std::string describe() const;

 private:
  double unclamped(double t) const;
  std::vector<double> times_{0.0};
  std::vector<double> values_{0.0};
  bool linear_ = false;       // λ(t) = values_[0] + slope_ t
  double slope_ = 0.0;
  std::function<double(double)> function_;  // set: λ(t) = function_(t)
  std::string name_;
};

}  // namespace aggkit
