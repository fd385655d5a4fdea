// Engine "dem": the 3-D soft-sphere DEM with optional self-gravity of particle/dem/ [Trivino2025] on the
// scene's [particles] (per-particle radii and masses, open/periodic/reflecting boundaries, cold clouds).
// Everything an ensemble shares comes from the particle runner; this file is the engine's options and one
// realization. The runner's `threads` runs realizations at once; `force_threads` runs the integration,
// contacts and gravity of one realization on several threads (results do not depend on it).
// The options, the contact-law calibration, the default step and the dashpot rule are particle/dem's
// (dem_parameters.hpp: DemParameters, dem_option_rows(), calibrate()); warnings about the step go to the
// observer (summary.json and the terminal).
// Its states give collision_frequency, virial_pressure and compressibility_factor (validation/observables/):
// collisions are pairs that start to overlap, the virial ∫ Σ r_ij·F_ij dt over the contacts.
// final.json gains steps, collisions, clamped_contacts, max_overlap (δ/R_min), realised_restitution,
// adhesive_fraction (particle/dem/dem.hpp: contact episodes still open at the end over all with an overlap),
// aggregation_time (NaN when the largest cluster never held the threshold), max_friction_ratio (with
// friction), energy_drift (elastic runs: no damping), and with gravity potential_energy (−Σ G m_i m_j / r_ij,
// unsoftened), virial_ratio (K/|P|), free_fall_time and aggregation_time_ff, and dashpot_solves and
// dashpot_iterations when the dashpots are integrated implicitly (particle/dem/implicit_dashpot.hpp). With
// gravity and no stop rule, the observe.final values, K/|P| and the largest cluster's mass fraction at T_agg
// as <name>_at_agg; with gravity, observe.times_ff (t_ff of the start, particle_runner.hpp).
// `gravity_substeps` K > 1 evaluates gravity every K contact steps (impulse splitting, particle/dem/dem.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

#include "analysis/input_error.hpp"
#include "particle/common/particle_system.hpp"
#include "particle/dem/contact_law.hpp"
#include "particle/dem/dashpot_scheme.hpp"
#include "particle/dem/dem.hpp"
#include "particle/dem/dem_parameters.hpp"
#include "particle/common/box_configuration.hpp"
#include "validation/engines/particle_runner.hpp"
#include "validation/io/machine.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

const OptionTable& dem_options() {
  static const OptionTable table = option_table(dem_option_rows());
  return table;
}

// What one realization runs with (calibrate() and the stop rule of DemParameters).
struct Settings {
  DemSettings dem;
  bool stop_aggregated = false;
  double threshold = 0;  // DemParameters::aggregation_threshold
  double realised_restitution = 0;
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
    // The reference radius is the mean; unequal radii go along, so contacts are within R_i + R_j (as the
    // engine's own cluster labels).
    ParticleConfiguration config = configuration_in(dem_.box(), mean / double(dem_.size()), dem_.positions());
    const std::vector<double>& radii = dem_.radii();
    if (std::adjacent_find(radii.begin(), radii.end(), std::not_equal_to<>()) != radii.end()) config.radii = radii;
    return config;
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
  bool saves_state() const override { return true; }
  void save(StateWriter& out) const override {
    dem_.save(out);
    out.put(aggregation_time_);
    out.put(std::uint64_t(at_aggregation_.size()));
    for (const auto& [key, value] : at_aggregation_) {
      out.put(key);
      out.put(value);
    }
  }
  void restore(StateReader& in) override {
    dem_.restore(in);
    in.get(aggregation_time_);
    at_aggregation_.resize(in.length(2 * sizeof(std::uint64_t)));  // key length, value
    for (auto& [key, value] : at_aggregation_) {
      in.get(key);
      in.get(value);
    }
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
  DemParameters parameters;
  given.read(dem_option_rows(), parameters);
  // particle/dem names the options in its own terms ("gravity.G"); the scene's key is engine[i].gravity.G.
  const auto rekey = [&given](const std::string& key) { return key.rfind("particles.", 0) == 0 ? key : given.key(key); };
  // Realization 0's start gives the masses the default time step is measured on.
  const DemCalibration c = under_key(rekey, [&] { return calibrate(parameters, system.initial_state(0), system.box); });
  const Settings settings{c.settings, parameters.stop_aggregated, parameters.aggregation_threshold, c.realised_restitution, c.elastic,
                          scene.observe.final_state};
  const DemSettings& dem = settings.dem;
  std::string warning;
  for (const std::string& w : c.step_notes) warning += "; WARNING " + w;
  if (!scene.observe.times_ff.empty() && !dem.gravity)
    throw InputError("observe.times_ff", "[" + format_value(scene.observe.times_ff.front()) + ", ...]",
                     "free-fall times need gravity = { G = ... } on engine dem (t_ff = √(R³/(G M)) [Trivino2025, eq. 9])");
  const Box box = system.box;
  std::string description = "soft-sphere DEM, k_n/m* " + format_value(dem.stiffness_per_mass) + ", γ_n/m* " + format_value(dem.damping_per_mass) +
                            ", k_n " + format_value(dem.stiffness) + ", γ_n " + format_value(dem.damping) + ", dt " + format_value(dem.dt) +
                            (dem.friction > 0 ? ", friction μ " + format_value(dem.friction) : "") + (dem.gravity ? (dem.tree ? ", tree gravity (θ " + format_value(dem.opening_angle) + ") G " : ", direct gravity G ") + format_value(dem.G) +
                                               (dem.gravity_substeps > 1 ? " every " + std::to_string(dem.gravity_substeps) + " steps" : "")
                                         : ", no gravity") +
                            (c.implicit_dashpot ? ", implicit dashpot (γ_n dt/m_eff " + format_value(c.damping_factor) + ")"
                             : parameters.dashpot == DashpotScheme::explicit_verlet ? ", explicit dashpot (γ_n dt/m_eff " + format_value(c.damping_factor) + ")"
                                                                                    : "") +
                            (settings.stop_aggregated ? ", stop when aggregated" : ", stop at time.end") + warning;
  return {[system, settings, box](std::size_t r) { return std::make_unique<DemSimulation>(box, system.initial_state(r), settings); },
          description, dem_option_rows().values(parameters), c.warnings};
}

}  // namespace

EngineType dem_engine_type() {
  return particle_engine_type({"dem", "3-D soft-sphere DEM with spring–dashpot contacts and optional self-gravity ([particles])",
                               dem_options(), setup_dem, need::particles | need::collisions | need::virial});
}

}  // namespace aggkit
