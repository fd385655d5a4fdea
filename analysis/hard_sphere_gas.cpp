#include "analysis/hard_sphere_gas.hpp"

#include <cmath>
#include <stdexcept>

namespace aggkit {

namespace {
void check(int dimension, double phi) {
  if (dimension != 2 && dimension != 3) throw std::invalid_argument("hard-sphere gas: dimension 2 or 3");
  if (!(phi >= 0 && phi < 1)) throw std::invalid_argument("hard-sphere gas: volume fraction in [0, 1)");
}
}  // namespace

double hard_sphere_compressibility(int dimension, double phi) {
  check(dimension, phi);
  const double q = 1 - phi;
  if (dimension == 3) return (1 + phi + phi * phi - phi * phi * phi) / (q * q * q);  // [Carnahan1969]
  return (1 + phi * phi / 8) / (q * q);                                             // [Henderson1975]
}

double hard_sphere_contact_value(int dimension, double phi) {
  check(dimension, phi);
  const double q = 1 - phi;
  // Z = 1 + 2^(d−1) φ χ solved for χ with the Z above, written without the 0/0 at φ = 0.
  if (dimension == 3) return (1 - phi / 2) / (q * q * q);
  return (1 - 7 * phi / 16) / (q * q);
}

double enskog_collision_frequency(int dimension, double n, double sigma, double kt_over_m, double phi) {
  const double chi = hard_sphere_contact_value(dimension, phi);
  const double speed = std::sqrt(M_PI * kt_over_m);
  const double nu0 = dimension == 3 ? 4 * n * sigma * sigma * speed : 2 * n * sigma * speed;
  return chi * nu0;  // [Chapman1970, ch. 16]
}

}  // namespace aggkit
