#include "particle/common/box.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "analysis/input_error.hpp"

namespace aggkit {

Boundary boundary_from_name(std::string_view name) {
  if (name == "periodic") return Boundary::periodic;
  if (name == "reflecting") return Boundary::reflecting;
  if (name == "open") return Boundary::open;
  throw InputError("boundary", "\"" + std::string(name) + "\"", "\"periodic\", \"reflecting\" or \"open\"");
}

std::string to_string(Boundary boundary) {
  switch (boundary) {
    case Boundary::periodic: return "periodic";
    case Boundary::reflecting: return "reflecting";
    case Boundary::open: return "open";
  }
  return "unknown";
}

double Box::volume() const {
  if (boundary == Boundary::open) return std::numeric_limits<double>::infinity();
  double v = 1.0;
  for (int d = 0; d < dimension; ++d) v *= side[d];
  return v;
}

Vector3 Box::minimum_image(const Vector3& displacement) const {
  if (boundary != Boundary::periodic) return displacement;
  Vector3 r = displacement;
  for (int d = 0; d < dimension; ++d) r[d] -= side[d] * std::nearbyint(r[d] / side[d]);
  return r;
}

Vector3 Box::wrap(const Vector3& position) const {
  if (boundary != Boundary::periodic) return position;
  Vector3 r = position;
  for (int d = 0; d < dimension; ++d) {
    r[d] -= side[d] * std::floor(r[d] / side[d]);
    if (r[d] >= side[d]) r[d] = 0.0;  // -tiny wraps to L in floating point
  }
  return r;
}

void Box::validate() const {
  if (dimension != 2 && dimension != 3) throw InputError("dimension", std::to_string(dimension), "2 or 3");
  if (boundary == Boundary::open) return;  // no box
  for (int d = 0; d < dimension; ++d)
    if (!std::isfinite(side[d]) || side[d] <= 0) throw InputError("box", format_value(side[d]), "box sides finite and > 0");
}

double particle_volume(int dimension, double radius) {
  return dimension == 2 ? std::numbers::pi * radius * radius : 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

double box_side_for_volume_fraction(int dimension, std::size_t count, double radius, double volume_fraction) {
  return std::pow(double(count) * particle_volume(dimension, radius) / volume_fraction, 1.0 / dimension);
}

double volume_fraction(const Box& box, std::size_t count, double radius) {
  return double(count) * particle_volume(box.dimension, radius) / box.volume();
}

}  // namespace aggkit
