#pragma once
// The DEM as a scene describes it [Trivino2025] and its calibration into the settings Dem runs with.
// Contact law: exactly one of (restitution, contact_time), (stiffness, damping) or
// (stiffness_normalized, damping) [Trivino2025, eqs. 2, 6, 15], with the corrected calibration
// k_n = m*(π² + ln² e)/t_c², γ_n = −2 m* ln(e)/t_c, or `calibration = "exact"`: γ_n solved so that the
// clipped binary collision returns e (contact_law.hpp). The step: t_c/50 by default, and with an explicit
// dashpot (friction) at most m_eff/(5 γ_n); refused above t_c/2, warned about above t_c/20 [Trivino2025,
// eq. 8] and, explicit, above m_eff/(5 γ_n). Friction (μ > 0) is refused with reflecting walls (they are
// frictionless), gravity in a periodic box (it would need Ewald sums).
#include <optional>
#include <string>
#include <vector>

#include "analysis/option_rows.hpp"
#include "particle/common/box.hpp"
#include "particle/common/particle_start.hpp"
#include "particle/dem/dem.hpp"

namespace aggkit {

struct DemParameters {
  // The contact law, in one of three forms (above).
  std::optional<double> restitution, contact_time;           // e, t_c
  std::optional<double> stiffness, damping;                  // k_n, γ_n for every pair
  std::optional<double> stiffness_normalized;                // k̃_n = k_n R³/(G m²) (mean R, m; with gravity)
  bool exact_calibration = false;                            // calibration = "exact"
  std::optional<double> dt;                                  // none: the step rule (above)
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
  // that is refused (the contact-law forms, opening_angle without the tree, gravity_substeps without gravity).
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
  std::vector<std::string> warnings;  // a step beyond the rules of thumb ("dt > t_c/20 = ...")
};

// k_n and γ_n from the contact law, the default step, the dashpot rule, checked against the start (its
// masses and radii: a realization's initial state) and the box. InputError naming the option or the
// [particles] key.
DemCalibration calibrate(const DemParameters& parameters, const ParticleStart& start, const Box& box);

}  // namespace aggkit
