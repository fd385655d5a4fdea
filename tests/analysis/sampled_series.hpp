#pragma once
// A function sampled at equal spacing from t = 0: the synthetic series of the oscillation tests.
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

namespace aggkit::testing {

inline const double two_pi = 2 * std::acos(-1.0);

struct Series {
  std::vector<double> t, x;
};

// f at 0, dt, 2 dt, … up to `end`.
inline Series sample(double end, double dt, const std::function<double(double)>& f) {
  Series s;
  for (std::size_t i = 0; double(i) * dt <= end + 1e-12; ++i) {
    s.t.push_back(double(i) * dt);
    s.x.push_back(f(double(i) * dt));
  }
  return s;
}

}  // namespace aggkit::testing
