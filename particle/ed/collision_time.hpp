#pragma once
// Contact time of two spheres in free flight: the smallest root t >= 0 of |Δx + Δv t| = σ (σ = R_i + R_j),
// i.e. of a t² + 2 b t + c = 0 with a = |Δv|², b = Δx·Δv, c = |Δx|² − σ² ([Allen2017, §3.7]). Only
// approaching pairs (b < 0) with a real root collide. The root is taken as t = c / (−b + sqrt(b² − a c)),
// which has no cancellation (−b > 0), unlike (−b − sqrt(..))/a.
// A pair that already overlaps by round-off (c < 0) while approaching collides at once (t = 0).
#include <cmath>
#include <limits>

#include "particle/common/vector3.hpp"

namespace aggkit {

inline double collision_time(const Vector3& dx, const Vector3& dv, double sigma) {
  const double b = dot(dx, dv);
  if (b >= 0) return std::numeric_limits<double>::infinity();
  const double c = dot(dx, dx) - sigma * sigma;
  if (c <= 0) return 0.0;
  const double a = dot(dv, dv);
  const double discriminant = b * b - a * c;
  if (discriminant < 0) return std::numeric_limits<double>::infinity();
  return c / (-b + std::sqrt(discriminant));
}

}  // namespace aggkit
