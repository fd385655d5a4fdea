#pragma once
// When do two axis-aligned boxes in relative uniform motion overlap? Along each axis the relative centre
// coordinate is y(t) = y0 + w t and the boxes overlap while |y − k L| <= s for some integer k (s: half the sum
// of the two extents; L the period of a periodic axis, 0 for none). The boxes overlap when every axis does:
// the first such interval from t = 0 on is found by advancing t to the latest per-axis window start until
// all axes overlap at once (the broad phase of the cluster-level ED engine, event_driven_aggregation.hpp).
#include <cmath>
#include <limits>

#include "particle/common/vector3.hpp"

namespace aggkit {

struct OverlapWindow {
  enum Kind { none, overlap, recheck } kind = none;  // recheck: not resolved by `begin`; ask again then
  double begin = 0, end = 0;
};

// The window along one axis that contains t or starts first after it; false if there is none.
inline bool axis_overlap(double y0, double w, double s, double period, double t, double& begin, double& end) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (period > 0 && s >= 0.5 * period) {
    begin = t;
    end = inf;
    return true;
  }
  double y = y0 + w * t;
  if (period > 0) y -= period * std::nearbyint(y / period);
  if (std::abs(y) <= s) {
    begin = t;
    end = w > 0 ? t + (s - y) / w : w < 0 ? t + (y + s) / -w : inf;
    return true;
  }
  if (w == 0) return false;
  const double speed = std::abs(w);
  if (period > 0) {
    double distance = std::fmod(w > 0 ? -s - y : y - s, period);
    if (distance < 0) distance += period;
    begin = t + distance / speed;
    end = begin + 2 * s / speed;
    return true;
  }
  if ((w > 0 && y < -s) || (w < 0 && y > s)) {
    begin = t + (std::abs(y) - s) / speed;
    end = t + (std::abs(y) + s) / speed;
    return true;
  }
  return false;
}

// The first overlap from t = 0 on, skipping windows shorter than `min_length` (callers inflate the boxes so
// that a true contact lies inside a window longer than that). After `iterations` steps without one, or once
// the search has passed `horizon`, a recheck at the time reached (a lower bound of the first overlap): along
// periodic axes the per-axis windows of small boxes recur every period and rarely coincide, so an
// unbounded search would step through many periods.
inline OverlapWindow first_overlap(int dimension, const Vector3& y0, const Vector3& w, const Vector3& s,
                                   const Vector3& period, double min_length, int iterations = 64,
                                   double horizon = std::numeric_limits<double>::infinity()) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double t = 0;
  for (int iteration = 0; iteration < iterations && t < horizon; ++iteration) {
    double begin = t, end = inf;
    bool all_now = true;
    for (int a = 0; a < dimension; ++a) {
      double b, e;
      if (!axis_overlap(y0[a], w[a], s[a], period[a], t, b, e)) return {};
      if (b > t) all_now = false;
      begin = std::max(begin, b);
      end = std::min(end, e);
    }
    if (all_now) {
      if (end - t > min_length) return {OverlapWindow::overlap, t, end};
      t = end + min_length;
      continue;
    }
    t = begin;
  }
  return {OverlapWindow::recheck, t, t};
}

}  // namespace aggkit
