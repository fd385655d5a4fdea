#include "particle/dem/dem_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/text.hpp"
#include "particle/dem/contact_law.hpp"

namespace aggkit {

const OptionRows<DemParameters>& dem_option_rows() {
  using P = DemParameters;
  using B = Bind<P>;
  const auto forces = [](auto member) { return [member](auto& p) -> auto& { return p.forces.*member; }; };
  static const OptionRows<P> rows{{
      B::number("restitution", &P::restitution, left_open(0.0, 1.0), "restitution e of a binary collision (with contact_time)", "none"),
      B::number("contact_time", &P::contact_time, greater_than(0.0), "contact time t_c (with restitution): k_n = m*(π² + ln² e)/t_c²",
                "none"),
      B::number("stiffness", &P::stiffness, greater_than(0.0), "k_n for every pair (with damping)", "none"),
      B::number("damping", &P::damping, at_least(0.0), "γ_n for every pair (with stiffness or stiffness_normalized)", "none"),
      B::number("stiffness_normalized", &P::stiffness_normalized, greater_than(0.0),
                "k̃_n = k_n R³/(G m²) with the mean radius and mass (with damping and gravity) [Trivino2025, eq. 15]", "none"),
      B::word("calibration", &P::exact_calibration, std::vector<std::pair<std::string, bool>>{{"formula", false}, {"exact", true}},
              "formula: γ_n = −2 m* ln(e)/t_c; exact: γ_n such that the clipped binary collision returns e (k_n of the formula)"),
      B::number("friction", forces(&DemSettings::friction), at_least(0.0),
                "Coulomb coefficient μ: tangential spring with history per contact, rotation (not at walls: refused with "
                "reflecting walls)"),
      B::number("tangential_stiffness_ratio", forces(&DemSettings::tangential_stiffness_ratio), left_open(0.0, 1e3),
                "k_t / k_n of the tangential spring (with friction)", "2/7"),
      B::number("dt", &P::dt, greater_than(0.0),
                "time step (refused above t_c/2, warned above t_c/20 [Trivino2025, eq. 8] and above m_eff/(5 γ_n))",
                "t_c/50; explicit dashpot: min(t_c/50, m_eff/(5 γ_n))"),
      B::number("steps_per_contact", &P::steps_per_contact, closed(2.0, 1e9),
                "N: dt = t_c/N with t_c of [Trivino2025, eq. 8] (instead of dt; for sweeps over the stiffness at a fixed "
                "resolution), N >= 2",
                "none"),
      B::word("dashpot", &P::dashpot,
              std::vector<std::pair<std::string, DashpotScheme>>{{dashpot_scheme_word(DashpotScheme::automatic), DashpotScheme::automatic},
                                                                 {dashpot_scheme_word(DashpotScheme::explicit_verlet), DashpotScheme::explicit_verlet},
                                                                 {dashpot_scheme_word(DashpotScheme::implicit), DashpotScheme::implicit}},
              "normal dashpot: explicit (stable while x = γ_n dt/m* < 1, warned above), implicit (stable at any x), "
              "auto (implicit above x = 0.2 without friction) (particle/dem/dashpot_scheme.hpp)"),
      B::table("gravity", "self-gravity G m_i m_j/(r² + ε²) along each pair [Trivino2025, eq. 1]", "off",
               {
                   B::number("G", &P::G, greater_than(0.0), "the gravitational constant"),
                   B::number("softening", &P::softening, at_least(0.0), "ε", "1e-3 R_min"),
                   B::word("method", forces(&DemSettings::tree), std::vector<std::pair<std::string, bool>>{{"direct", false}, {"tree", true}},
                           "direct pairwise sums or a Barnes–Hut tree"),
                   B::number("opening_angle", &P::opening_angle, left_open(0.0, 1.0), "θ of the tree (method = \"tree\" only)",
                             shortest_text(DemSettings{}.opening_angle)),
               },
               [](const P& p) { return p.forces.gravity; }, [](P& p) { p.forces.gravity = true; }),
      B::custom("stop", "\"aggregated\"", "\"aggregated\": stop once the largest cluster holds aggregation_threshold of the mass",
                "at time.end", [](const P& p) { return p.stop_aggregated ? nlohmann::json("aggregated") : nlohmann::json(); },
                [](P& p, const nlohmann::json& value, const std::string& key) {
                  if (!value.is_string() || value.get<std::string>() != "aggregated") throw InputError(key, option_text(value), "\"aggregated\"");
                  p.stop_aggregated = true;
                }),
      B::number("aggregation_threshold", &P::aggregation_threshold, left_open(0.0, 1.0),
                "mass fraction of the largest cluster that defines T_agg"),
      B::number("contact_tolerance", forces(&DemSettings::contact_tolerance), closed(0.0, 1.0),
                "contact graph: centre distance < R_i + R_j + contact_tolerance · R_min"),
      B::integer("gravity_substeps", forces(&DemSettings::gravity_substeps), closed(1, 100000),
                 "impulse splitting: gravity evaluated every K contact steps, kicks of K dt/2 (r-RESPA)"),
      B::integer("force_threads", forces(&DemSettings::force_threads), closed(1, 4096),
                 "threads for the integration, contacts and gravity of one realization (results do not depend on it)"),
  }};
  return rows;
}

namespace {

const char* const missing = "(missing)";

}  // namespace

void DemParameters::validate() const {
  dem_option_rows().check(*this);
  const bool by_restitution = restitution || contact_time;
  const std::string forms = "exactly one of (restitution, contact_time), (stiffness, damping), (stiffness_normalized, damping)";
  if (int(by_restitution) + int(bool(stiffness)) + int(bool(stiffness_normalized)) != 1) {
    if (stiffness && stiffness_normalized) throw InputError("stiffness_normalized", shortest_text(*stiffness_normalized), forms);
    if (by_restitution && stiffness) throw InputError("stiffness", shortest_text(*stiffness), forms);
    if (by_restitution && stiffness_normalized) throw InputError("stiffness_normalized", shortest_text(*stiffness_normalized), forms);
    throw InputError("restitution", missing, forms);
  }
  if (by_restitution) {
    if (!restitution) throw InputError("restitution", missing, "a number in (0, 1] with contact_time");
    if (!contact_time) throw InputError("contact_time", missing, "a number > 0 with restitution");
    if (damping) throw InputError("damping", shortest_text(*damping), "no damping with (restitution, contact_time)");
  } else {
    if (exact_calibration)
      throw InputError("calibration", "\"exact\"", "\"formula\" (exact calibration needs restitution and contact_time)");
    if (!damping)
      throw InputError("damping", missing, "a number >= 0 with " + std::string(stiffness ? "stiffness" : "stiffness_normalized"));
    if (stiffness_normalized && !forces.gravity)
      throw InputError("stiffness_normalized", shortest_text(*stiffness_normalized),
                       "stiffness (stiffness_normalized = k_n R³/(G m²) needs gravity = { G = ... })");
  }
  if (dt && steps_per_contact)
    throw InputError("steps_per_contact", shortest_text(*steps_per_contact), "either dt or steps_per_contact, not both");
  if (dashpot == DashpotScheme::implicit && forces.friction > 0)
    throw InputError("dashpot", "\"implicit\"", "\"auto\" or \"explicit\" with friction (the implicit dashpot has no tangential springs)");
  if (forces.gravity && !G) throw InputError("gravity.G", missing, "a number > 0");
  if (opening_angle && !forces.tree)
    throw InputError("gravity.opening_angle", shortest_text(*opening_angle), "an opening angle only with method = \"tree\"");
  if (forces.gravity_substeps > 1 && !forces.gravity) throw InputError("gravity_substeps", std::to_string(forces.gravity_substeps), "1 without gravity");
}

namespace {

// The contact law's key and value, named by a calibration that leaves the doubles (a contact time or a
// stiffness so small that k_n, γ_n or the damping ratio overflow, or the step underflows).
struct LawKey {
  const char* key;
  double value;
  explicit LawKey(const DemParameters& p)
      : key(p.restitution ? "contact_time" : p.stiffness ? "stiffness" : "stiffness_normalized"),
        value(p.restitution ? *p.contact_time : p.stiffness ? *p.stiffness : *p.stiffness_normalized) {}
  void representable(double x, const std::string& what) const {
    if (!std::isfinite(x))
      throw InputError(key, shortest_text(value), "a contact law whose " + what + " is a finite number (here " + shortest_text(x) + ")");
  }
};

// A law given by restitution e and contact time t_c: k_n/m* and γ_n/m*.
void calibrate_by_restitution(const DemParameters& p, const LawKey& law, DemCalibration& c) {
  DemSettings& dem = c.settings;
  const double e = *p.restitution;
  c.contact_time = *p.contact_time;
  const double log_e = std::log(e);
  const double rate = (M_PI * M_PI + log_e * log_e) / (c.contact_time * c.contact_time);  // k_n / m*
  dem.stiffness_per_mass = rate;
  // ζ = γ/(2√(k m*)): the formula's −ln e/√(π² + ln² e), or the root of the clipped collision.
  double zeta = 0;
  try {
    zeta = p.exact_calibration ? exact_damping_ratio(e) : formula_damping_ratio(e);
  } catch (const std::invalid_argument& error) {  // a restitution below what the exact calibration reaches
    throw InputError("restitution", shortest_text(e), std::string("a restitution the exact calibration reaches: ") + error.what());
  }
  dem.damping_per_mass = 2 * zeta * std::sqrt(rate);
  law.representable(rate, "k_n/m* = (π² + ln² e)/t_c²");
  law.representable(dem.damping_per_mass, "γ_n/m*");
  c.realised_restitution = clipped_collision(zeta).restitution;
  c.elastic = e == 1;
}

// A law given by stiffness (or its normalized form) and damping; `reference_reduced` the m_eff of t_c.
void calibrate_by_stiffness(const DemParameters& p, const LawKey& law, double mean_mass, double mean_radius,
                            double reference_reduced, DemCalibration& c) {
  DemSettings& dem = c.settings;
  dem.damping = *p.damping;
  if (p.stiffness) {
    dem.stiffness = *p.stiffness;
  } else {
    // k* = G m²/R³ with the mean mass and radius [Trivino2025, eqs. 14–15].
    dem.stiffness = *p.stiffness_normalized * dem.G * mean_mass * mean_mass / (mean_radius * mean_radius * mean_radius);
  }
  c.contact_time = M_PI * std::sqrt(reference_reduced / dem.stiffness);  // [Trivino2025, eq. 8]
  // The realised restitution of a pair of mean masses.
  const double reduced = 0.5 * mean_mass;
  const double zeta = dem.damping / (2 * std::sqrt(dem.stiffness * reduced));
  law.representable(dem.stiffness, "k_n");
  law.representable(zeta, "damping ratio γ_n/(2√(k_n m*))");
  law.representable(c.contact_time, "contact time π√(m_eff/k_n)");
  c.realised_restitution = clipped_collision(zeta).restitution;
  c.elastic = dem.damping == 0;
}

// The step (given, or from the contact and dashpot times) with its checks, notes and warnings.
// The dashpot's own time m_eff/γ_n (fastest for the lightest pair): the explicit dashpot relaxes a contact's
// normal velocity by a factor 1 − γ_n dt/m* per step, which overshoots and reverses it once γ_n dt/m* > 1 —
// an overdamped collision then rebounds instead of sticking (measured: γ_n = 2·10^4 at k̃_n = 10^6 with
// dt = t_c/50 left the whole cloud unaggregated). `dashpot = "auto"` integrates such dashpots implicitly
// without friction (implicit_dashpot.hpp: stable at any step), so the default step stays t_c/50; an explicit
// dashpot (`dashpot = "explicit"`, or auto with friction) gets a default step that resolves it with 5 steps;
// a given step is taken as given, warned above t_c/20 or x > 1 (dashpot_scheme.hpp).
void choose_step(const DemParameters& p, const LawKey& law, DemCalibration& c) {
  DemSettings& dem = c.settings;
  const double damping_time = c.damping_rate > 0 ? 1 / c.damping_rate : std::numeric_limits<double>::infinity();
  const bool explicit_dashpot =
      p.dashpot == DashpotScheme::explicit_verlet || (p.dashpot == DashpotScheme::automatic && dem.friction > 0);
  const double t_c = c.contact_time;
  dem.dt = p.dt                  ? *p.dt
           : p.steps_per_contact ? t_c / *p.steps_per_contact
           : explicit_dashpot    ? std::min(t_c / 50, damping_time / 5)
                                 : t_c / 50;
  const char* step_key = p.dt ? "dt" : p.steps_per_contact ? "steps_per_contact" : law.key;
  const double step_value = p.dt ? *p.dt : p.steps_per_contact ? *p.steps_per_contact : law.value;
  if (!(dem.dt > 0))
    throw InputError(step_key, shortest_text(step_value),
                     "a step dt > 0 (here t_c = " + shortest_text(t_c) + " gives dt = " + shortest_text(dem.dt) + ")");
  if (dem.dt > t_c / 2)
    throw InputError("dt", shortest_text(dem.dt), "dt <= t_c/2 = " + shortest_text(t_c / 2) + " (a contact must span several steps)");
  const DashpotStepCheck step = check_dashpot_step(p.dashpot, c.damping_rate * dem.dt, dem.dt, t_c, dem.friction > 0);
  c.damping_factor = step.damping_factor;
  c.warnings = step.warnings;
  if (dem.dt > t_c / 20) c.step_notes.push_back("dt > t_c/20 = " + shortest_text(t_c / 20) + " [Trivino2025, eq. 8]");
  if (explicit_dashpot && dem.dt > damping_time / 5) {
    c.step_notes.push_back("dt > m_eff/(5 γ_n) = " + shortest_text(damping_time / 5) + " (the dashpot is under-resolved)");
    if (step.damping_factor <= 1)  // beyond 1 the stability warning says more
      c.warnings.push_back("dt = " + shortest_text(dem.dt) + " > m_eff/(5 γ_n) = " + shortest_text(damping_time / 5) +
                           ": the explicit dashpot is under-resolved (x = γ_n dt/m* = " + shortest_text(step.damping_factor) + ")");
  }
  if (!step.implicit && step.damping_factor > 1) c.step_notes.push_back("explicit dashpot above its stability limit x > 1");
}

}  // namespace

DemCalibration calibrate(const DemParameters& p, const ParticleStart& start, const Box& box) {
  p.validate();
  DemCalibration c;
  DemSettings& dem = c.settings;
  dem = p.forces;
  if (dem.friction > 0 && box.boundary == Boundary::reflecting)
    throw InputError("friction", shortest_text(dem.friction),
                     "0 with boundary = \"reflecting\" (the walls are frictionless: wall friction is not implemented yet)");
  if (dem.gravity) {
    if (box.boundary == Boundary::periodic)
      throw InputError("particles.boundary", "\"periodic\"", "\"open\" or \"reflecting\" with gravity (a periodic box would need Ewald sums)");
    dem.G = *p.G;
    if (p.softening) dem.softening = *p.softening;
    if (p.opening_angle) dem.opening_angle = *p.opening_angle;
  }

  // The start's masses give the default step; the mean mass and radius the normalized stiffness.
  const double m_min = *std::min_element(start.masses.begin(), start.masses.end());
  double mean_mass = 0, mean_radius = 0;
  for (std::size_t i = 0; i < start.size(); ++i) mean_mass += start.masses[i], mean_radius += start.radii[i];
  mean_mass /= double(start.size());
  mean_radius /= double(start.size());

  const bool by_restitution = p.restitution.has_value();
  const LawKey law(p);
  const double reference_reduced = 0.5 * m_min;  // [Trivino2025, eq. 8]: m_eff ≈ min(m_i)/2
  if (by_restitution) calibrate_by_restitution(p, law, c);
  else calibrate_by_stiffness(p, law, mean_mass, mean_radius, reference_reduced, c);
  dem.implicit_dashpot_above = implicit_dashpot_threshold(p.dashpot);
  c.damping_rate = by_restitution ? dem.damping_per_mass : dem.damping / reference_reduced;
  choose_step(p, law, c);
  c.implicit_dashpot = implicit_dashpot_wanted(dem, m_min);
  return c;
}

}  // namespace aggkit
