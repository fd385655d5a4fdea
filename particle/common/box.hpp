#pragma once
// The simulation box [0, L_x) x [0, L_y) (x [0, L_z)) with periodic or reflecting boundaries, or open space
// (no box: particles move freely in R^d, e.g. a cloud under self-gravity), and the relation between particle
// count, radius and volume fraction ν = N·v_1/L^d (v_1 = πR² or 4πR³/3).
#include <cstddef>
#include <string>
#include <string_view>

#include "particle/common/vector3.hpp"

namespace aggkit {

enum class Boundary {
  periodic,    // the box tiles space
  reflecting,  // walls at 0 and L_d
  open,        // no box: unbounded space; the sides are unused
};

Boundary boundary_from_name(std::string_view name);  // "periodic" | "reflecting" | "open"; InputError otherwise
std::string to_string(Boundary boundary);

struct Box {
  int dimension = 2;          // 2 or 3
  Vector3 side{1.0, 1.0, 0.0};  // L_d per axis (side[2] unused in 2-D; all unused when open)
  Boundary boundary = Boundary::periodic;

  double volume() const;  // area in 2-D; +inf when open
  // The displacement b - a reduced to the nearest periodic image (unchanged for reflecting walls and open).
  Vector3 minimum_image(const Vector3& displacement) const;
  // The position brought into [0, L) along periodic axes (unchanged for reflecting walls and open).
  Vector3 wrap(const Vector3& position) const;
  // Throws InputError for a dimension other than 2 or 3 or (unless open) a side that is not finite and > 0.
  void validate() const;
};

// Area (2-D) or volume (3-D) of one particle of radius R.
double particle_volume(int dimension, double radius);
// Side L of the square/cubic box holding N particles of radius R at volume fraction ν: L^d = N v_1 / ν.
double box_side_for_volume_fraction(int dimension, std::size_t count, double radius, double volume_fraction);
double volume_fraction(const Box& box, std::size_t count, double radius);

}  // namespace aggkit
