#pragma once
// Equilibrium hard-sphere (3-D) and hard-disc (2-D) gas: the equation of state and the collision frequency,
// the independent check of the particle engines' collision_frequency and virial_pressure observables.
//   Compressibility factor Z = P V / (N k T): Carnahan–Starling in 3-D [Carnahan1969],
//     Z = (1 + φ + φ² − φ³) / (1 − φ)³;  Henderson in 2-D [Henderson1975], Z = (1 + φ²/8) / (1 − φ)².
//   Contact value of the pair correlation χ = g(σ⁺) from the exact virial relation of hard spheres
//     Z = 1 + 2^(d−1) φ χ [Allen2017, ch. 2], i.e. χ = (1 − φ/2)/(1 − φ)³ (3-D), (1 − 7φ/16)/(1 − φ)² (2-D).
//   Collisions per particle per unit time (each collision counted for both partners), Enskog's
//     ν_E = χ ν_0 [Chapman1970, ch. 16], ν_0 = 4 n σ² √(π k T/m) (3-D), 2 n σ √(π k T/m) (2-D): the Boltzmann
//     rate n · (collision cross-section π σ² or width 2σ) · mean relative speed (4√(kT/(π m)) in 3-D,
//     √(π k T/m) in 2-D). In equilibrium ν = χ ν_0 is exact given the true χ; the model is only χ.
// σ = 2R is the contact distance, n = N/V, φ = n v(R) the volume (area) fraction.
namespace aggkit {

double hard_sphere_compressibility(int dimension, double volume_fraction);  // Z (CS or Henderson)
double hard_sphere_contact_value(int dimension, double volume_fraction);    // χ = g(σ⁺)
// ν_E for number density n, diameter σ and k T / m.
double enskog_collision_frequency(int dimension, double number_density, double diameter, double temperature_over_mass,
                                  double volume_fraction);

}  // namespace aggkit
