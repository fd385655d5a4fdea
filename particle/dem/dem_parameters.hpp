#pragma once
// The DEM as a scene describes it [Trivino2025] and its calibration into the settings Dem runs with.
// Contact law: exactly one of (restitution, contact_time), (stiffness, damping) or
// (stiffness_normalized, damping) [Trivino2025, eqs. 2, 6, 15], with the corrected calibration
// k_n = m*(π² + ln² e)/t_c², γ_n = −2 m* ln(e)/t_c, or `calibration = "exact"`: γ_n solved so that the
// clipped binary collision returns e (contact_law.hpp). The normal dashpot is integrated explicitly or
// implicitly (`dashpot`, dashpot_scheme.hpp). The step: dt, or t_c/steps_per_contact, or by default t_c/50,
// and with an explicit dashpot (`dashpot = "explicit"`, or auto with friction) at most m_eff/(5 γ_n); refused
// above t_c/2, warned about above t_c/20 [Trivino2025, eq. 8], with an explicit dashpot above x = γ_n dt/m* = 1
// (its stability limit) and above m_eff/(5 γ_n). Friction (μ > 0) is refused with reflecting walls (they are
// frictionless) and with the implicit dashpot (it has no tangential springs), gravity in a periodic box (it
// would need Ewald sums).
#include <optional>
#include <string>
#include <vector>

#include "analysis/option_rows.hpp"
#include "particle/common/box.hpp"
#include "particle/common/particle_start.hpp"
#include "particle/dem/dashpot_scheme.hpp"
#include "particle/dem/dem.hpp"

namespace aggkit {

struct DemParameters {
  // The contact law, in one of three forms (above).
  std::optional<double> restitution, contact_time;           // e, t_c
  std::optional<double> stiffness, damping;                  // k_n, γ_n for every pair
  std::optional<double> stiffness_normalized;                // k̃_n = k_n R³/(G m²) (mean R, m; with gravity)
  bool exact_calibration = false;                            // calibration = "exact"
  std::optional<double> dt;                                  // none: the step rule (above)
  std::optional<double> steps_per_contact;                   // N: dt = t_c/N (not with dt)
  DashpotScheme dashpot = DashpotScheme::automatic;          // how the normal dashpot is integrated
  // Self-gravity (gravity = { ... }): on, G (required), ε (none: 1e-3 R_min), θ (tree only; none: the
  // settings' default); the method and the rest of the forces are `forces`' own fields.
  std::optional<double> G, softening, opening_angle;
  // friction, tangential_stiffness_ratio, contact_tolerance, gravity, tree, gravity_substeps, force_threads
  // as Dem takes them; calibrate() fills in the rest.
  DemSettings forces;
  // The end of the run: stop once the largest cluster holds aggregation_threshold of the mass (T_agg).
  bool stop_aggregated = false;
  double aggregation_threshold = 0.9;

  // InputError, naming the option ("gravity.G", ...), for a value outside its row's range or a combination
  // that is refused (the contact-law forms, dt with steps_per_contact, the implicit dashpot with friction,
  // opening_angle without the tree, gravity_substeps without gravity).
  void validate() const;
};

// The options of engine dem as a scene and Python give them: key, range, doc and the field each sets.
const OptionRows<DemParameters>& dem_option_rows();

// What calibrate() decides.
struct DemCalibration {
  DemSettings settings;          // what Dem runs with
  double contact_time = 0;       // t_c of the lightest pair (m_eff = m_min/2) [Trivino2025, eq. 8]
  double damping_rate = 0;       // γ_n/m_eff of the lightest pair (1/time)
  double realised_restitution = 0;  // of a binary collision (pairs of mean mass for (k_n, γ_n) given)
  bool elastic = false;          // no damping: the energy is conserved
  bool implicit_dashpot = false; // as Dem decides (implicit_dashpot_wanted)
  double damping_factor = 0;     // x = γ_n dt/m* of the lightest pair
  // A step beyond the rules of thumb, one sentence each (check_dashpot_step's, and an explicit dashpot
  // under-resolved below its stability limit), for the observer; `step_notes` the same in brief for the
  // engine's one-line description ("dt > t_c/20 = ...", "dt > m_eff/(5 γ_n) = ...", "explicit dashpot above
  // its stability limit x > 1").
  std::vector<std::string> warnings, step_notes;
};

// k_n and γ_n from the contact law, the default step, the dashpot rule, checked against the start (its
// masses and radii: a realization's initial state) and the box. InputError naming the option or the
// [particles] key.
DemCalibration calibrate(const DemParameters& parameters, const ParticleStart& start, const Box& box);

}  // namespace aggkit
