#include "solvers/shattering_rate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/input_error.hpp"

namespace aggkit {

ShatteringRate ShatteringRate::constant(double lambda) { return table({0.0}, {lambda}); }

ShatteringRate ShatteringRate::linear(double initial, double slope) {
  ShatteringRate r;
  r.times_ = {0.0, 1.0};
  r.values_ = {initial, initial + slope};
  r.linear_ = true;
  r.slope_ = slope;
  return r;
}

ShatteringRate ShatteringRate::table(std::vector<double> times, std::vector<double> values) {
  if (times.empty() || times.size() != values.size())
    throw InputError("lambda.times", std::to_string(times.size()) + " entries",
                     "needs as many times as values (" + std::to_string(values.size()) + "), at least one");
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]))
      throw InputError("lambda.times[" + std::to_string(i) + "]", format_value(times[i]), "must be finite");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError("lambda.times[" + std::to_string(i) + "]", format_value(times[i]),
                       "times must be strictly increasing");
  }
  ShatteringRate r;
  r.times_ = std::move(times);
  r.values_ = std::move(values);
  return r;
}

ShatteringRate ShatteringRate::function(std::function<double(double)> lambda, std::string name) {
  ShatteringRate r;
  r.function_ = std::move(lambda);
  r.name_ = std::move(name);
  return r;
}

double ShatteringRate::operator()(double t) const {
  // Values within round-off below zero (e.g. a linear law that reaches 0 exactly at the end) are 0;
  // validate() has checked that nothing more negative occurs on [0, end].
  return std::max(0.0, unclamped(t));
}

double ShatteringRate::unclamped(double t) const {
  if (function_) return function_(t);
  if (linear_) return values_[0] + slope_ * t;
  if (times_.size() == 1 || t <= times_.front()) return values_.front();
  if (t >= times_.back()) return values_.back();
  // Linear interpolation on the bracketing segment.
  const std::size_t seg = std::size_t(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
  const double w = (t - times_[seg - 1]) / (times_[seg] - times_[seg - 1]);
  return values_[seg - 1] + w * (values_[seg] - values_[seg - 1]);
}

void ShatteringRate::validate(double t_end, const std::string& key) const {
  // λ(t) is piecewise linear, so its extremes on [0, t_end] are at 0, t_end and the table's knots.
  std::vector<double> probes{0.0, t_end};
  for (double t : times_)
    if (t > 0.0 && t < t_end) probes.push_back(t);
  if (function_)  // a function is only sampled: 1001 points on [0, t_end]
    for (int i = 1; i < 1000; ++i) probes.push_back(t_end * i / 1000.0);
  double scale = 0.0;
  for (double v : values_) scale = std::max(scale, std::abs(v));
  for (double t : probes) {
    const double value = unclamped(t);
    if (!std::isfinite(value)) throw InputError(key, format_value(value), "the shattering rate must be finite");
    if (value < -1e-12 * scale)  // below round-off
      throw InputError(key, describe(),
                       "the shattering rate must be >= 0 on [0, end]; it is " + format_value(value) +
                           " at t = " + format_value(t));
  }
}

std::string ShatteringRate::describe() const {
  std::ostringstream out;
  if (function_) {
    out << name_;
  } else if (times_.size() == 1) {
    out << format_value(values_[0]);
  } else if (linear_) {
    out << format_value(values_[0]) << (slope_ < 0 ? " - " : " + ") << format_value(std::abs(slope_)) << " t";
  } else {
    out << "table(";
    for (std::size_t i = 0; i < times_.size(); ++i)
      out << (i ? ", " : "") << format_value(times_[i]) << ":" << format_value(values_[i]);
    out << ")";
  }
  return out.str();
}

}  // namespace aggkit
