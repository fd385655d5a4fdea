// Engine "dem": the 3-D soft-sphere DEM with optional self-gravity of particle/dem/ [Trivino2025] on the
// scene's [particles] (per-particle radii and masses, open/periodic/reflecting boundaries, cold clouds).
// Everything an ensemble shares comes from the particle runner; this file is the engine's options and one
// realization. The runner's `threads` runs realizations at once; `force_threads` runs the integration,
// contacts and gravity of one realization on several threads (results do not depend on it).
// Contact law: exactly one of (restitution, contact_time), (stiffness, damping) or
// (stiffness_normalized, damping) [Trivino2025, eqs. 2, 6, 15], with the corrected calibration
// k_n = m*(π² + ln² e)/t_c², γ_n = −2 m* ln(e)/t_c, or `calibration = "exact"`: γ_n solved so that the
// clipped binary collision returns e (particle/dem/contact_law.hpp).
// Friction (μ > 0): tangential springs with history and rotation (particle/dem/dem.hpp); the walls are
// frictionless, so friction is refused with reflecting walls.
// Its states give collision_frequency, virial_pressure and compressibility_factor (validation/observables/):
// collisions are pairs that start to overlap, the virial ∫ Σ r_ij·F_ij dt over the contacts.
// final.json gains steps, collisions, clamped_contacts, max_overlap (δ/R_min), realised_restitution,
// adhesive_fraction (particle/dem/dem.hpp: contact episodes still open at the end over all with an overlap),
// aggregation_time (NaN when the largest cluster never held the threshold), max_friction_ratio (with
// friction), energy_drift (elastic runs: no damping), and with gravity potential_energy (−Σ G m_i m_j / r_ij,
// unsoftened), virial_ratio (K/|P|), free_fall_time and aggregation_time_ff, and dashpot_solves and
// dashpot_iterations when the dashpots are integrated implicitly (particle/dem/implicit_dashpot.hpp).
// `gravity_substeps` K > 1 evaluates gravity every K contact steps (impulse splitting, particle/dem/dem.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>

#include "analysis/input_error.hpp"
#include "particle/common/particle_system.hpp"
#include "particle/dem/contact_law.hpp"
#include "particle/dem/dashpot_scheme.hpp"
#include "particle/dem/dem.hpp"
#include "particle/common/box_configuration.hpp"
#include "validation/engines/particle_runner.hpp"
#include "validation/io/machine.hpp"

namespace aggkit {

namespace {

const OptionTable& dem_options() {
  static const OptionTable table{
      number_option("restitution", "none", "restitution e of a binary collision (with contact_time)", 0.0, 1.0, true),
      number_option("contact_time", "none", "contact time t_c (with restitution): k_n = m*(π² + ln² e)/t_c²", 0.0,
                    std::numeric_limits<double>::infinity(), true),
      number_option("stiffness", "none", "k_n for every pair (with damping)", 0.0, std::numeric_limits<double>::infinity(), true),
      number_option("damping", "none", "γ_n for every pair (with stiffness or stiffness_normalized)", 0.0,
                    std::numeric_limits<double>::infinity()),
      number_option("stiffness_normalized", "none",
                    "k̃_n = k_n R³/(G m²) with the mean radius and mass (with damping and gravity) [Trivino2025, eq. 15]", 0.0,
                    std::numeric_limits<double>::infinity(), true),
      word_option("calibration", "formula",
                  "formula: γ_n = −2 m* ln(e)/t_c; exact: γ_n such that the clipped binary collision returns e (k_n of the formula)",
                  {"formula", "exact"}),
      number_option("friction", "0",
                    "Coulomb coefficient μ: tangential spring with history per contact, rotation (not at walls: refused with "
                    "reflecting walls)",
                    0.0, std::numeric_limits<double>::infinity()),
      number_option("tangential_stiffness_ratio", "2/7", "k_t / k_n of the tangential spring (with friction)", 0.0, 1e3, true),
      number_option("dt", "t_c/50; explicit dashpot: min(t_c/50, m_eff/(5 γ_n))",
                    "time step (refused above t_c/2, warned above t_c/20 [Trivino2025, eq. 8] and above m_eff/(5 γ_n))", 0.0,
                    std::numeric_limits<double>::infinity(), true),
      custom_option("gravity", "off", "self-gravity G m_i m_j/(r² + ε²) along each pair [Trivino2025, eq. 1]",
                    "{ G = number > 0, softening = number >= 0 (default 1e-3 R_min), method = \"direct\" | \"tree\", "
                    "opening_angle = θ in (0, 1] (tree; default 0.5) }"),
      custom_option("stop", "at time.end", "\"aggregated\": stop once the largest cluster holds aggregation_threshold of the mass",
                    "\"aggregated\""),
      number_option("aggregation_threshold", "0.9", "mass fraction of the largest cluster that defines T_agg", 0.0, 1.0, true),
      number_option("contact_tolerance", "0.01", "contact graph: centre distance < R_i + R_j + contact_tolerance · R_min", 0.0, 1.0),
      integer_option("gravity_substeps", "1",
                     "impulse splitting: gravity evaluated every K contact steps, kicks of K dt/2 (r-RESPA)", 1, 100000),
      number_option("steps_per_contact", "none",
                    "N: dt = t_c/N with t_c of [Trivino2025, eq. 8] (instead of dt; for sweeps over the stiffness at a fixed "
                    "resolution), N >= 2",
                    2.0, 1e9),
      word_option("dashpot", "auto",
                  "normal dashpot: explicit (stable while x = γ_n dt/m* < 1, warned above), implicit (stable at any x), "
                  "auto (implicit above x = 0.2 without friction) (particle/dem/dashpot_scheme.hpp)",
                  {"auto", "explicit", "implicit"}),
      integer_option("force_threads", "1", "threads for the integration, contacts and gravity of one realization (results do not depend on it)", 1, 4096),
  };
  return table;
}

struct Settings {
  DemSettings dem;
  bool stop_aggregated = false;
  double threshold = 0.9;
  double realised_restitution = std::numeric_limits<double>::quiet_NaN();
  bool elastic = false;
  // Runs that go on past T_agg record these observe.final observables (and K/|P|) at T_agg too, as
  // <name>_at_agg (NaN where the run never aggregates).
  std::vector<std::string> at_aggregation;
};

class DemSimulation final : public ParticleSimulation {
 public:
  DemSimulation(const Box& box, ParticleStart start, const Settings& settings)
      : settings_(settings), dem_(box, std::move(start), settings.dem) {
    // Free-fall time t_ff = √(R_c³/(G M)), R_c the largest distance from the initial centre of mass
    // [Trivino2025, eq. 9].
    if (settings.dem.gravity) {
      Vector3 centre{0, 0, 0};
      double total = 0;
      for (std::size_t i = 0; i < dem_.size(); ++i) centre = centre + dem_.masses()[i] * dem_.positions()[i], total += dem_.masses()[i];
      centre = (1 / total) * centre;
      double reach = 0;
      for (const Vector3& p : dem_.positions()) reach = std::max(reach, norm(p - centre));
      free_fall_ = std::sqrt(reach * reach * reach / (settings.dem.G * total));
    }
    energy0_ = dem_.total_energy();
    energy_scale_ = dem_.kinetic_energy() + std::abs(dem_.gravitational_energy()) + dem_.elastic_energy();
    check_aggregated();
  }

  bool advance(double t, const StatusSink& status) override {
    if (aggregated()) return true;
    const double dt = settings_.dem.dt;
    std::uint64_t since = 0;
    while (dem_.time() + 0.5 * dt <= t) {
      dem_.step();
      check_aggregated();
      if (aggregated()) return true;
      if (++since % 4096 == 0) report(status);
    }
    return false;
  }

  double time() const override { return dem_.time(); }
  double free_fall_time() const override { return free_fall_; }
  std::vector<std::pair<std::string, double>> state_values() const override {
    if (!settings_.dem.gravity) return {};
    const double potential = potential_energy();
    return {{"virial_ratio", dem_.kinetic_energy() / std::abs(potential)},
            {"largest_cluster_mass_fraction", dem_.largest_cluster_mass_fraction()}};
  }
  ParticleConfiguration configuration() const override {
    double mean = 0;
    for (double r : dem_.radii()) mean += r;
    // One radius: the mean (the engine's own cluster labels use R_i + R_j).
    return configuration_in(dem_.box(), mean / double(dem_.size()), dem_.positions());
  }
  std::vector<Vector3> velocities() const override { return dem_.velocities(); }
  std::vector<double> masses() const override { return dem_.masses(); }
  std::vector<std::uint32_t> cluster_labels() const override { return dem_.cluster_labels(); }
  std::vector<Vector3> largest_cluster() const override {
    if (dem_.box().boundary == Boundary::periodic) return ParticleSimulation::largest_cluster();
    const std::vector<std::uint32_t> labels = dem_.cluster_labels();
    std::vector<std::size_t> sizes(dem_.size(), 0);
    for (std::uint32_t l : labels) ++sizes[l];
    const std::uint32_t largest = std::uint32_t(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
    std::vector<Vector3> out;
    for (std::size_t i = 0; i < labels.size(); ++i)
      if (labels[i] == largest) out.push_back(dem_.positions()[i]);
    return out;
  }
  double kinetic_energy() const override { return dem_.kinetic_energy(); }
  std::vector<double> radii() const override { return dem_.radii(); }
  // Rotation is integrated only with friction: without it the snapshot has no angular_velocity array.
  std::vector<Vector3> angular_velocities() const override {
    return settings_.dem.friction > 0 ? dem_.angular_velocities() : std::vector<Vector3>{};
  }
  Vector3 momentum() const override { return dem_.momentum(); }
  Vector3 wall_impulse() const override { return dem_.wall_impulse(); }
  std::optional<CollisionStatistics> collision_statistics() const override {
    const DemCounters& c = dem_.counters();
    return CollisionStatistics{dem_.time(), double(c.collisions), c.virial_integral, c.kinetic_integral};
  }

  std::vector<std::pair<std::string, double>> final_values() const override {
    const DemCounters& c = dem_.counters();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<std::string, double>> values{{"steps", double(c.steps)},
                                                       {"collisions", double(c.collisions)},
                                                       {"adhesive_fraction", dem_.adhesive_fraction()},
                                                       {"clamped_contacts", double(c.clamped_contacts)},
                                                       {"max_overlap", c.max_overlap},
                                                       {"realised_restitution", settings_.realised_restitution}};
    if (settings_.dem.friction > 0) values.emplace_back("max_friction_ratio", c.max_friction_ratio);  // max |F_t|/(μ F_n) ≤ 1
    if (dem_.implicit_dashpot()) {  // the implicit dashpot's cost: linear solves and conjugate-gradient iterations
      values.emplace_back("dashpot_solves", double(c.dashpot_solves));
      values.emplace_back("dashpot_iterations", double(c.dashpot_iterations));
    }
    if (settings_.dem.gravity) {
      const double potential = potential_energy();
      values.emplace_back("potential_energy", potential);
      values.emplace_back("virial_ratio", dem_.kinetic_energy() / std::abs(potential));
      values.emplace_back("free_fall_time", free_fall_);
      values.emplace_back("aggregation_time", aggregation_time_);
      values.emplace_back("aggregation_time_ff", aggregation_time_ / free_fall_);
    } else {
      values.emplace_back("aggregation_time", aggregation_time_);
    }
    if (!settings_.stop_aggregated && settings_.dem.gravity) {
      for (const auto& [key, value] : at_aggregation_) values.emplace_back(key, value);
      if (at_aggregation_.empty())  // never aggregated: the same entries, undefined
        for (const auto& [key, value] : aggregation_snapshot()) values.emplace_back(key, nan);
    }
    if (settings_.elastic)
      values.emplace_back("energy_drift", energy_scale_ > 0 ? std::abs(dem_.total_energy() - energy0_) / energy_scale_ : nan);
    return values;
  }
  std::vector<std::pair<std::string, std::int64_t>> counters() const override {
    const DemCounters& c = dem_.counters();
    return {{"steps", std::int64_t(c.steps)}, {"collisions", std::int64_t(c.collisions)}, {"clamped_contacts", std::int64_t(c.clamped_contacts)}};
  }

 private:
  bool aggregated() const { return settings_.stop_aggregated && !std::isnan(aggregation_time_); }
  void check_aggregated() {
    if (std::isnan(aggregation_time_) && dem_.largest_cluster_reaches(settings_.threshold)) {
      aggregation_time_ = dem_.time();
      if (!settings_.stop_aggregated && settings_.dem.gravity) at_aggregation_ = aggregation_snapshot();
    }
  }
  // The observe.final values and K/|P| of the current state, named <name>_at_agg.
  std::vector<std::pair<std::string, double>> aggregation_snapshot() const {
    std::vector<std::pair<std::string, double>> values = configuration_values(settings_.at_aggregation, ParticleView(*this), "_at_agg");
    for (const auto& [key, value] : state_values()) values.emplace_back(key + "_at_agg", value);
    return values;
  }
  // P = −Σ_{i<j} G m_i m_j / r_ij [Trivino2025, eq. 11]: the unsoftened potential of K/|P|.
  double potential_energy() const {
    const auto& x = dem_.positions();
    const auto& m = dem_.masses();
    double potential = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = i + 1; j < x.size(); ++j) potential -= settings_.dem.G * m[i] * m[j] / norm(x[j] - x[i]);
    return potential;
  }
  void report(const StatusSink& status) const {
    char line[96];
    std::snprintf(line, sizeof line, "t = %.6g, %llu steps, largest cluster %.3g of the mass", dem_.time(),
                  static_cast<unsigned long long>(dem_.counters().steps), dem_.largest_cluster_mass_fraction());
    status(line);
  }

  Settings settings_;
  Dem dem_;
  std::vector<std::pair<std::string, double>> at_aggregation_;  // aggregation_snapshot() at T_agg
  double free_fall_ = std::numeric_limits<double>::quiet_NaN();
  double aggregation_time_ = std::numeric_limits<double>::quiet_NaN();
  double energy0_ = 0, energy_scale_ = 0;
};

void check_particles(const ParticleSystem& system) {
  if (system.box.dimension != 3) throw InputError("particles.dimension", std::to_string(system.box.dimension), "3 for engine dem");
  // Positions, velocities, forces, radii, masses, cell grid and pair lists: well under 1 kB per particle.
  check_memory("particles.count", std::to_string(system.count), 1e3 * double(system.count), "engine dem: about 1 kB per particle");
}

ParticleEngineKind::Setup setup_dem(const EngineOptions& given, const Scene& scene) {
  const ParticleSystem& system = *scene.particles;
  check_particles(system);
  Settings settings;
  DemSettings& dem = settings.dem;

  dem.friction = given.number("friction", 0.0);
  dem.tangential_stiffness_ratio = given.number("tangential_stiffness_ratio", dem.tangential_stiffness_ratio);
  if (dem.friction > 0 && system.box.boundary == Boundary::reflecting)
    given.fail("friction", "0 with boundary = \"reflecting\" (the walls are frictionless: wall friction is not implemented yet)");

  if (given.has("gravity")) {
    const nlohmann::json& g = given.value("gravity");
    const std::string forms = "{ G = number > 0, softening = number >= 0, method = \"direct\" | \"tree\", opening_angle = θ }";
    if (!g.is_object()) given.fail("gravity", forms);
    for (auto it = g.begin(); it != g.end(); ++it)
      if (it.key() != "G" && it.key() != "softening" && it.key() != "method" && it.key() != "opening_angle")
        throw InputError(given.key("gravity") + "." + it.key(), option_text(it.value()), "a key of " + forms);
    if (!g.contains("G") || !g["G"].is_number() || !(g["G"].get<double>() > 0))
      throw InputError(given.key("gravity") + ".G", g.contains("G") ? option_text(g["G"]) : "(missing)", "a number > 0");
    if (system.box.boundary == Boundary::periodic)
      throw InputError("particles.boundary", "\"periodic\"", "\"open\" or \"reflecting\" with gravity (a periodic box would need Ewald sums)");
    dem.gravity = true;
    dem.G = g["G"].get<double>();
    if (g.contains("softening")) {
      if (!g["softening"].is_number() || !(g["softening"].get<double>() >= 0) || !std::isfinite(g["softening"].get<double>()))
        throw InputError(given.key("gravity") + ".softening", option_text(g["softening"]), "a finite number >= 0");
      dem.softening = g["softening"].get<double>();
    }
    if (g.contains("method")) {
      const nlohmann::json& m = g["method"];
      if (!m.is_string() || (m.get<std::string>() != "direct" && m.get<std::string>() != "tree"))
        throw InputError(given.key("gravity") + ".method", option_text(m), "\"direct\" or \"tree\"");
      dem.tree = m.get<std::string>() == "tree";
    }
    if (g.contains("opening_angle")) {
      const nlohmann::json& a = g["opening_angle"];
      if (!a.is_number() || !(a.get<double>() > 0 && a.get<double>() <= 1))
        throw InputError(given.key("gravity") + ".opening_angle", option_text(a), "a number in (0, 1]");
      if (!dem.tree)
        throw InputError(given.key("gravity") + ".opening_angle", option_text(a), "an opening angle only with method = \"tree\"");
      dem.opening_angle = a.get<double>();
    }
  }

  // Realization 0's start gives the masses the default time step is measured on.
  const ParticleStart start0 = system.initial_state(0);
  const double m_min = *std::min_element(start0.masses.begin(), start0.masses.end());
  double mean_mass = 0, mean_radius = 0;
  for (std::size_t i = 0; i < start0.size(); ++i) mean_mass += start0.masses[i], mean_radius += start0.radii[i];
  mean_mass /= double(start0.size());
  mean_radius /= double(start0.size());

  const bool by_restitution = given.has("restitution") || given.has("contact_time");
  const bool by_stiffness = given.has("stiffness");
  const bool by_normalized = given.has("stiffness_normalized");
  const std::string forms = "exactly one of (restitution, contact_time), (stiffness, damping), (stiffness_normalized, damping)";
  if (int(by_restitution) + int(by_stiffness) + int(by_normalized) != 1) {
    if (by_stiffness && by_normalized) given.fail("stiffness_normalized", forms);
    if (by_restitution && (by_stiffness || by_normalized)) given.fail(by_stiffness ? "stiffness" : "stiffness_normalized", forms);
    throw InputError(given.key("restitution"), "(missing)", forms);
  }
  const bool exact = given.word("calibration", "formula") == "exact";
  double contact_time = 0;  // t_c for the default step and its checks
  const double reference_reduced = 0.5 * m_min;  // [Trivino2025, eq. 8]: m_eff ≈ min(m_i)/2
  if (by_restitution) {
    if (!given.has("restitution")) throw InputError(given.key("restitution"), "(missing)", "a number in (0, 1] with contact_time");
    if (!given.has("contact_time")) throw InputError(given.key("contact_time"), "(missing)", "a number > 0 with restitution");
    if (given.has("damping")) given.fail("damping", "no damping with (restitution, contact_time)");
    const double e = given.number("restitution", 1.0);
    contact_time = given.number("contact_time", 1.0);
    const double log_e = std::log(e);
    const double rate = (M_PI * M_PI + log_e * log_e) / (contact_time * contact_time);  // k_n / m*
    dem.stiffness_per_mass = rate;
    // ζ = γ/(2√(k m*)): the formula's −ln e/√(π² + ln² e), or the root of the clipped collision.
    const double zeta = exact ? exact_damping_ratio(e) : formula_damping_ratio(e);
    dem.damping_per_mass = 2 * zeta * std::sqrt(rate);
    settings.realised_restitution = clipped_collision(zeta).restitution;
    settings.elastic = e == 1;
  } else {
    if (exact) given.fail("calibration", "\"formula\" (exact calibration needs restitution and contact_time)");
    if (!given.has("damping")) throw InputError(given.key("damping"), "(missing)", "a number >= 0 with " + std::string(by_stiffness ? "stiffness" : "stiffness_normalized"));
    dem.damping = given.number("damping", 0.0);
    if (by_stiffness) {
      dem.stiffness = given.number("stiffness", 1.0);
    } else {
      if (!dem.gravity)
        given.fail("stiffness_normalized", "stiffness (stiffness_normalized = k_n R³/(G m²) needs gravity = { G = ... })");
      // k* = G m²/R³ with the mean mass and radius [Trivino2025, eqs. 14–15].
      dem.stiffness = given.number("stiffness_normalized", 1.0) * dem.G * mean_mass * mean_mass / (mean_radius * mean_radius * mean_radius);
    }
    contact_time = M_PI * std::sqrt(reference_reduced / dem.stiffness);  // [Trivino2025, eq. 8]
    // The realised restitution of a pair of mean masses.
    const double reduced = 0.5 * mean_mass;
    settings.realised_restitution = clipped_collision(dem.damping / (2 * std::sqrt(dem.stiffness * reduced))).restitution;
    settings.elastic = dem.damping == 0;
  }
  // The dashpot's own time m_eff/γ_n (fastest for the lightest pair): the explicit dashpot relaxes a contact's
  // normal velocity by a factor 1 − γ_n dt/m* per step, which overshoots and reverses it once γ_n dt/m* > 1 —
  // an overdamped collision then rebounds instead of sticking (measured: γ_n = 2·10^4 at k̃_n = 10^6 with
  // dt = t_c/50 left the whole cloud unaggregated). `dashpot = "auto"` integrates such dashpots implicitly
  // without friction (particle/dem/implicit_dashpot.hpp: stable at any step), so the default step stays t_c/50;
  // an explicit dashpot (`dashpot = "explicit"`, or auto with friction) gets a default step that resolves it
  // with 5 steps; a given step is taken as given, warned above t_c/20 or x > 1 (particle/dem/dashpot_scheme.hpp).
  const DashpotScheme scheme = dashpot_scheme_from_word(given.word("dashpot", "auto"));
  if (scheme == DashpotScheme::implicit && dem.friction > 0)
    given.fail("dashpot", "\"auto\" or \"explicit\" with friction (the implicit dashpot has no tangential springs)");
  dem.implicit_dashpot_above = implicit_dashpot_threshold(scheme);
  const double damping_rate = by_restitution ? dem.damping_per_mass : dem.damping / reference_reduced;  // 1/time
  const double damping_time = damping_rate > 0 ? 1 / damping_rate : std::numeric_limits<double>::infinity();
  const bool explicit_dashpot = scheme == DashpotScheme::explicit_verlet || (scheme == DashpotScheme::automatic && dem.friction > 0);
  if (given.has("dt") && given.has("steps_per_contact")) given.fail("steps_per_contact", "either dt or steps_per_contact, not both");
  dem.dt = given.has("dt")                  ? given.number("dt", 0.0)
           : given.has("steps_per_contact") ? contact_time / given.number("steps_per_contact", 50.0)
           : explicit_dashpot               ? std::min(contact_time / 50, damping_time / 5)
                                            : contact_time / 50;
  if (dem.dt > contact_time / 2)
    given.fail("dt", "dt <= t_c/2 = " + format_value(contact_time / 2) + " (a contact must span several steps)");
  const DashpotStepCheck step_check = check_dashpot_step(scheme, damping_rate * dem.dt, dem.dt, contact_time, dem.friction > 0);
  std::vector<std::string> warnings = step_check.warnings;
  std::string warning;
  if (dem.dt > contact_time / 20) warning = "; WARNING dt > t_c/20 = " + format_value(contact_time / 20) + " [Trivino2025, eq. 8]";
  if (explicit_dashpot && dem.dt > damping_time / 5) {
    warning += "; WARNING dt > m_eff/(5 γ_n) = " + format_value(damping_time / 5) + " (the dashpot is under-resolved)";
    if (step_check.damping_factor <= 1)
      warnings.push_back("dt = " + format_value(dem.dt) + " > m_eff/(5 γ_n) = " + format_value(damping_time / 5) +
                         ": the explicit dashpot is under-resolved (x = γ_n dt/m* = " + format_value(step_check.damping_factor) + ")");
  }
  if (!step_check.implicit && step_check.damping_factor > 1) warning += "; WARNING explicit dashpot above its stability limit x > 1";
  const bool implicit = step_check.implicit;  // as Dem decides
  dem.contact_tolerance = given.number("contact_tolerance", dem.contact_tolerance);
  dem.force_threads = std::size_t(given.integer("force_threads", 1));
  dem.gravity_substeps = std::size_t(given.integer("gravity_substeps", 1));
  if (dem.gravity_substeps > 1 && !dem.gravity) given.fail("gravity_substeps", "1 without gravity");
  settings.threshold = given.number("aggregation_threshold", 0.9);
  settings.at_aggregation = scene.observe.final_state;
  if (!scene.observe.times_ff.empty() && !dem.gravity)
    throw InputError("observe.times_ff", "[" + format_value(scene.observe.times_ff.front()) + ", ...]",
                     "free-fall times need gravity = { G = ... } on engine dem (t_ff = √(R³/(G M)) [Trivino2025, eq. 9])");
  if (given.has("stop")) {
    const nlohmann::json& stop = given.value("stop");
    if (!stop.is_string() || stop.get<std::string>() != "aggregated") given.fail("stop", "\"aggregated\"");
    settings.stop_aggregated = true;
  }
  const Box box = system.box;
  std::string description = "soft-sphere DEM, k_n/m* " + format_value(dem.stiffness_per_mass) + ", γ_n/m* " + format_value(dem.damping_per_mass) +
                            ", k_n " + format_value(dem.stiffness) + ", γ_n " + format_value(dem.damping) + ", dt " + format_value(dem.dt) +
                            (dem.friction > 0 ? ", friction μ " + format_value(dem.friction) : "") + (dem.gravity ? (dem.tree ? ", tree gravity (θ " + format_value(dem.opening_angle) + ") G " : ", direct gravity G ") + format_value(dem.G) +
                                               (dem.gravity_substeps > 1 ? " every " + std::to_string(dem.gravity_substeps) + " steps" : "")
                                         : ", no gravity") +
                            (implicit ? ", implicit dashpot (γ_n dt/m_eff " + format_value(damping_rate * dem.dt) + ")"
                             : scheme == DashpotScheme::explicit_verlet ? ", explicit dashpot (γ_n dt/m_eff " + format_value(damping_rate * dem.dt) + ")"
                                                                        : "") +
                            (settings.stop_aggregated ? ", stop when aggregated" : ", stop at time.end") + warning;
  return {[system, settings, box](std::size_t r) { return std::make_unique<DemSimulation>(box, system.initial_state(r), settings); },
          description, warnings};
}

}  // namespace

EngineType dem_engine_type() {
  return particle_engine_type({"dem", "3-D soft-sphere DEM with spring–dashpot contacts and optional self-gravity ([particles])",
                               dem_options(), setup_dem, need::particles | need::collisions | need::virial});
}

}  // namespace aggkit
