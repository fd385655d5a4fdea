#pragma once
// How the normal dashpot γ_n v_n of the contacts is integrated over a velocity-Verlet step, and what a step
// costs its stability [Trivino2025, eqs. 6, 8].
//   explicit: the dashpot force from the predicted velocity (dem.hpp). A pair's pure dashpot multiplies its
//             normal relative velocity by 1 − x per step, x = γ_n dt/m*: stable and dissipative only while
//             x < 1; beyond, an overdamped approach is reversed and the pair gains energy (x = 2.2 returns
//             e ≈ 1.2 where the closed form gives ≈ 0). With dt = t_c/N and damping ratio
//             ζ = γ_n/(2√(k_n m*)), x = 2πζ/N (t_c = π√(m*/k_n)): the paper's only bound dt ≤ t_c/20 (eq. 8)
//             allows x = 0.35 at ζ = 1.12, and nothing bounds the damping time m*/γ_n.
//   implicit: the θ-method of implicit_dashpot.hpp, stable at any x (the exact relaxation e^{−x} of a pair).
//   automatic: implicit once the largest x of the pairs exceeds `automatic_implicit_above` (and friction is
//             off: the implicit solve has no tangential springs), explicit below.
#include <string>
#include <string_view>
#include <vector>

namespace aggkit {

enum class DashpotScheme { automatic, explicit_verlet, implicit };

// "auto", "explicit", "implicit" (the scene words); std::invalid_argument for any other word.
DashpotScheme dashpot_scheme_from_word(std::string_view word);
const char* dashpot_scheme_word(DashpotScheme scheme);

// The largest x = γ_n dt/m* for which `automatic` keeps the explicit dashpot (its restitution is then within
// about 1e-3 of the closed form at dt = t_c/50: particle/dem tests).
inline constexpr double automatic_implicit_above = 0.2;

// The value of DemSettings::implicit_dashpot_above that realises `scheme`: +∞ explicit, 0 implicit.
double implicit_dashpot_threshold(DashpotScheme scheme);

// What a step does to the dashpots: x = γ_n dt/m* of the lightest pair (the largest over the pairs) and
// dt against t_c, and the warnings they call for.
struct DashpotStepCheck {
  double damping_factor = 0;      // x = γ_n dt/m* of the lightest pair
  double steps_per_contact = 0;   // t_c/dt
  bool implicit = false;          // the dashpots are integrated implicitly
  std::vector<std::string> warnings;  // one sentence each, empty when the step is within both bounds
};

// `damping_factor` x of the lightest pair at step dt, `contact_time` t_c of eq. 8; `friction`: the
// automatic scheme stays explicit with friction.
DashpotStepCheck check_dashpot_step(DashpotScheme scheme, double damping_factor, double dt, double contact_time, bool friction);

}  // namespace aggkit
