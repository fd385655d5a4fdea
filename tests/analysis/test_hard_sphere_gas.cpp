// The hard-sphere equation of state and collision frequency against what is known exactly: the ideal-gas
// limit, the exact virial relation Z = 1 + 2^(d−1) φ χ, and the exact low-density virial coefficients.
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis/hard_sphere_gas.hpp"

using namespace aggkit;

TEST_CASE("hard-sphere gas: ideal limit and the virial relation between Z and the contact value", "[hard_sphere]") {
  for (int d : {2, 3}) {
    CHECK(hard_sphere_compressibility(d, 0.0) == 1.0);
    CHECK(hard_sphere_contact_value(d, 0.0) == 1.0);
    for (double phi : {0.05, 0.15, 0.3, 0.45}) {
      const double z = hard_sphere_compressibility(d, phi), chi = hard_sphere_contact_value(d, phi);
      CHECK(z == Approx(1 + std::pow(2.0, d - 1) * phi * chi).epsilon(1e-14));
    }
  }
  // Enskog at φ → 0 is the Boltzmann rate n π σ² ⟨|v_rel|⟩, ⟨|v_rel|⟩ = 4 √(kT/(π m)) in 3-D, √(π kT/m) in 2-D.
  CHECK(enskog_collision_frequency(3, 0.3, 1.0, 0.5, 0.0) == Approx(0.3 * M_PI * 4 * std::sqrt(0.5 / M_PI)).epsilon(1e-14));
  CHECK(enskog_collision_frequency(2, 0.3, 1.0, 0.5, 0.0) == Approx(0.3 * 2 * std::sqrt(M_PI * 0.5)).epsilon(1e-14));
}

TEST_CASE("hard-sphere gas: the low-density virial coefficients", "[hard_sphere]") {
  // Z = 1 + B2 φ + B3 φ² + ...: exactly B2 = 4, B3 = 10 for spheres (Carnahan–Starling reproduces both) and
  // B2 = 2, B3 = 16/3 − 4√3/π = 3.1280 for discs (Henderson: 3.125). The finite differences below carry
  // O(φ) of the next coefficient: at φ = 1e-4 that is 2e-3 (B4 = 18) and 4e-4 (discs).
  const double phi = 1e-4;
  const double z3 = hard_sphere_compressibility(3, phi), z2 = hard_sphere_compressibility(2, phi);
  CHECK((z3 - 1) / phi == Approx(4).margin(2e-3));
  CHECK((z3 - 1 - 4 * phi) / (phi * phi) == Approx(10).margin(3e-3));
  CHECK((z2 - 1) / phi == Approx(2).margin(1e-3));
  CHECK((z2 - 1 - 2 * phi) / (phi * phi) == Approx(16.0 / 3 - 4 * std::sqrt(3.0) / M_PI).margin(4e-3));
}
