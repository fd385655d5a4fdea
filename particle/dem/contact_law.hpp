#pragma once
// The linear spring–dashpot normal contact of two spheres [Trivino2025, eqs. 2, 6, 7]:
//   F_n = k_n δ − γ_n v_n for δ = R_i + R_j − r > 0 (v_n the separation speed), set to 0 where it would
// attract. Its calibration from a restitution e and a contact time t_c uses the corrected formulas
//   k_n = m* (π² + ln² e) / t_c²,   γ_n = −2 m* ln(e) / t_c   (damping ratio ζ = −ln e / √(π² + ln² e)),
// i.e. ω_d = π / t_c, replacing the dimensionally inconsistent eqs. 3–4 of the paper. Because the force is
// clipped at zero the realised restitution of a binary collision is larger than e; `exact_damping_ratio`
// solves for the damping ratio at which the clipped collision returns e (GSL's Brent solver).
//
// Everything here is the dimensionless 1-D problem of one head-on collision: m* δ'' = −max(0, k δ + γ δ'),
// δ(0) = 0, δ'(0) = v0, in units of ω0 = √(k/m*) (times t ω0) and v0. It does not depend on v0.
namespace aggkit {

// One clipped binary collision at damping ratio ζ = γ / (2 √(k m*)) ≥ 0 (under-, critically or
// over-damped), solved in closed form.
struct ClippedCollision {
  double restitution;  // separation speed / approach speed once the spheres part
  double force_time;   // ω0 · (time at which the force reaches zero: from then on the spheres fly apart)
  double overlap_time; // ω0 · (time at which δ returns to 0: the geometric contact duration)
};
ClippedCollision clipped_collision(double damping_ratio);

// ζ of the corrected formula for restitution e in (0, 1]: −ln e / √(π² + ln² e) (0 for e = 1).
double formula_damping_ratio(double restitution);

// The ζ at which the clipped collision returns restitution e in (0, 1] (0 for e = 1), to a relative
// tolerance 1e-12 in ζ; Brent's method on clipped_collision(ζ).restitution − e, which falls monotonically
// from 1 (ζ = 0) towards 0. Throws std::invalid_argument for e outside (0, 1] or below what ζ ≤ 1e6 reaches.
double exact_damping_ratio(double restitution);

}  // namespace aggkit
