// Engine "ed": event-driven ballistic aggregation of the scene's [particles] (particle/ed/): hard discs or
// spheres of equal radius and mass that stick on contact into rigid clusters translating with the
// momentum-weighted velocity, exact contact times [Degond2024]. Everything an ensemble of realizations
// shares (series, final.json, profiles, snapshots, threads) comes from the particle runner; this file is the
// engine's options and one realization. final.json gains `events` and, with thermalisation, the elastic
// collisions before sticking (`thermalization_collisions`; run on particle/ed/elastic_gas.hpp, after which
// the clock restarts at 0).
// `collisions = "elastic"` runs the hard-sphere gas itself instead (particle/ed/elastic_gas.hpp: no
// sticking, every collision elastic, each particle its own cluster), with `thermalize` as a warm-up before
// the clock starts; its states give collision_frequency, virial_pressure and compressibility_factor,
// accumulated from t = 0 (the hard-sphere reference of soft-sphere DEM). final.json then gains `collisions`.
#include <algorithm>
#include <cstdio>
#include <limits>

#include "analysis/input_error.hpp"
#include "particle/ed/ed_configuration.hpp"
#include "particle/ed/ed_options.hpp"
#include "particle/common/box_configuration.hpp"
#include "particle/ed/elastic_gas.hpp"
#include "validation/io/machine.hpp"
#include "validation/engines/particle_runner.hpp"
#include "validation/engines/sticky_spheres.hpp"

namespace aggkit {

namespace {

// The physics' options (particle/ed/ed_options.hpp) and the runner's cluster target.
struct Settings {
  EdSettings ed;
  std::size_t target_clusters = 0;  // 0: stop at time.end
};

const OptionRows<Settings>& stop_rows() {
  static const OptionRows<Settings> rows{{cluster_stop_row(&Settings::target_clusters)}};
  return rows;
}

const OptionTable& ed_options() {
  static const OptionTable table = option_table(stop_rows(), ed_option_rows());  // stop first, as --help has always listed it
  return table;
}

class EdSimulation final : public ParticleSimulation {
 public:
  EdSimulation(const ParticleSystem& system, const ParticleStart& start, const Settings& settings)
      : ed_(system.box, system.mean_radius(), start.positions, start.velocities, true, settings.ed.cells),
        settings_(settings),
        mass_(system.mean_mass()) {}

  void prepare(const StatusSink& status) override {
    ed_.thermalize(settings_.ed.thermalize, [&](std::size_t pending) {
      status("thermalising: " + std::to_string(ed_.particles() - pending) + " of " + std::to_string(ed_.particles()) +
             " particles have " + std::to_string(settings_.ed.thermalize) + " collisions");
    });
    thermal_collisions_ = double(ed_.counters().elastic_collisions);
  }

  bool advance(double t, const StatusSink& status) override {
    return ed_.advance(t, settings_.target_clusters, [&] { report(status); }) == EdStop::clusters_reached;
  }

  // With a cluster target not reached by time.end, runs on in chunks until it is, or until no event remains
  // (nothing will ever change: the engine's events can be far apart, so a quiet chunk alone proves nothing).
  // The chunks start at time.end and double, so a system whose collisions are rare on the scale of time.end
  // (a tiny speed, a dilute box) still gets there in a number of chunks logarithmic in its time scale.
  void finish(double chunk, const StatusSink& status) override {
    if (settings_.target_clusters == 0) return;
    while (ed_.clusters() > settings_.target_clusters) {
      const auto before = ed_.counters().events();
      if (ed_.advance(ed_.time() + chunk, settings_.target_clusters, [&] { report(status); }) == EdStop::clusters_reached)
        return;
      if (ed_.counters().events() == before && ed_.exhausted()) return;
      report(status);
      chunk *= 2;
    }
  }

  double time() const override { return ed_.time(); }
  ParticleConfiguration configuration() const override { return aggkit::configuration(ed_); }
  std::vector<Vector3> velocities() const override { return ed_.velocities(); }
  std::vector<double> masses() const override { return std::vector<double>(ed_.particles(), mass_); }
  std::vector<std::uint32_t> cluster_labels() const override { return ed_.cluster_labels(); }
  std::vector<Vector3> largest_cluster() const override { return ed_.cluster_positions(ed_.largest_cluster()); }
  double kinetic_energy() const override { return mass_ * ed_.kinetic_energy(); }  // over clusters: O(C)
  Vector3 momentum() const override { return mass_ * ed_.momentum(); }
  Vector3 wall_impulse() const override { return mass_ * ed_.wall_impulse(); }

  std::vector<std::pair<std::string, double>> final_values() const override {
    std::vector<std::pair<std::string, double>> values{{"events", double(ed_.counters().events())}};
    if (settings_.ed.thermalize > 0) values.emplace_back("thermalization_collisions", thermal_collisions_);
    return values;
  }
  bool saves_state() const override { return true; }
  void save(StateWriter& out) const override {
    ed_.save(out);
    out.put(thermal_collisions_);
  }
  void restore(StateReader& in) override {
    ed_.restore(in);
    in.get(thermal_collisions_);
  }
  std::vector<std::pair<std::string, std::int64_t>> counters() const override {
    const EdCounters& c = ed_.counters();
    return {{"events", std::int64_t(c.events())},
            {"merges", std::int64_t(c.merges)},
            {"elastic_collisions", std::int64_t(c.elastic_collisions)},
            {"cell_crossings", std::int64_t(c.cell_crossings)},
            {"wall_contacts", std::int64_t(c.wall_contacts)},
            {"stale_events", std::int64_t(c.stale_events)}};
  }

 private:
  void report(const StatusSink& status) const {
    char t[32];
    std::snprintf(t, sizeof t, "%.6g", ed_.time());
    status("t = " + std::string(t) + ", " + std::to_string(ed_.clusters()) + " clusters");
  }

  mutable EventDrivenAggregation ed_;  // exhausted() skips stale events: a const query that pops the queue
  Settings settings_;
  double mass_;
  double thermal_collisions_ = 0;
};

// collisions = "elastic": the hard-sphere gas, measured from the end of its warm-up (thermalize) on.
class ElasticGasSimulation final : public ParticleSimulation {
 public:
  ElasticGasSimulation(const ParticleSystem& system, const ParticleStart& start, const EdSettings& settings)
      : gas_(make_elastic_gas(system.box, system.mean_radius(), start.positions, start.velocities)),
        thermalize_(settings.thermalize),
        mass_(system.mean_mass()),
        box_(system.box),
        radius_(system.mean_radius()) {}

  void prepare(const StatusSink& status) override {
    gas_->thermalize(thermalize_, [&](std::size_t pending) {
      status("thermalising: " + std::to_string(gas_->particles() - pending) + " of " + std::to_string(gas_->particles()) +
             " particles have " + std::to_string(thermalize_) + " collisions");
    });
    start_time_ = gas_->time();
    start_collisions_ = gas_->counters().collisions;
    start_virial_ = gas_->collision_virial();
    thermal_collisions_ = double(start_collisions_);
  }

  bool advance(double t, const StatusSink& status) override {
    gas_->advance(start_time_ + t);  // output times are the progress steps
    status("t = " + format_value(time()) + ", " + std::to_string(gas_->counters().collisions - start_collisions_) + " collisions");
    return false;
  }

  double time() const override { return gas_->time() - start_time_; }
  ParticleConfiguration configuration() const override {
    return configuration_in(box_, radius_, gas_->positions());
  }
  std::vector<Vector3> velocities() const override { return gas_->velocities(); }
  std::vector<double> masses() const override { return std::vector<double>(gas_->particles(), mass_); }
  std::vector<std::uint32_t> cluster_labels() const override {
    std::vector<std::uint32_t> labels(gas_->particles());
    for (std::uint32_t i = 0; i < labels.size(); ++i) labels[i] = i;
    return labels;
  }
  std::vector<Vector3> largest_cluster() const override { return {gas_->positions().front()}; }
  double kinetic_energy() const override { return mass_ * gas_->kinetic_energy(); }
  Vector3 momentum() const override { return mass_ * gas_->momentum(); }
  Vector3 wall_impulse() const override { return mass_ * gas_->wall_impulse(); }
  // Elastic: Σ m |v|² is constant, so its time integral is 2 K t.
  std::optional<CollisionStatistics> collision_statistics() const override {
    const double t = time();
    return CollisionStatistics{t, double(gas_->counters().collisions - start_collisions_),
                               mass_ * (gas_->collision_virial() - start_virial_), 2 * kinetic_energy() * t};
  }

  std::vector<std::pair<std::string, double>> final_values() const override {
    std::vector<std::pair<std::string, double>> values{{"events", double(gas_->counters().events())},
                                                       {"collisions", double(gas_->counters().collisions - start_collisions_)}};
    if (thermalize_ > 0) values.emplace_back("thermalization_collisions", thermal_collisions_);
    return values;
  }
  std::vector<std::pair<std::string, std::int64_t>> counters() const override {
    const ElasticGasCounters& c = gas_->counters();
    return {{"events", std::int64_t(c.events())},
            {"elastic_collisions", std::int64_t(c.collisions)},
            {"cell_crossings", std::int64_t(c.cell_crossings)},
            {"wall_contacts", std::int64_t(c.wall_contacts)},
            {"stale_events", std::int64_t(c.stale_events)}};
  }


 private:
  std::unique_ptr<ElasticGas> gas_;
  std::size_t thermalize_;
  double mass_;
  Box box_;
  double radius_;
  double start_time_ = 0, start_virial_ = 0, thermal_collisions_ = 0;
  std::uint64_t start_collisions_ = 0;
};

// The forms of [particles] this engine cannot use are refused, naming the key: its clusters are of equal
// hard spheres of one mass (the momentum-weighted velocity of a merge is then the mean), inside walls or a
// periodic box, and move ballistically, so they must move at the start.
void check_particles(const ParticleSystem& system) {
  require_sticky_spheres(system, "ed", "it has no forces to hold an open cloud", "without forces nothing would ever move");
  // Event times are absolute doubles: contacts must be resolved against positions of the box's magnitude
  // (L ε ≪ R, ε = 2.2e-16), and the time a particle needs to cross its radius must stay a normal double far
  // from under- and overflow (a speed of 1e300 made every event time ~1e-301 and the clock stall).
  const double R = system.mean_radius();
  double L = 0;
  for (int d = 0; d < system.box.dimension; ++d) L = std::max(L, system.box.side[d]);
  if (!(L / R <= 1e12))
    throw InputError("particles.box", format_value(L),
                     "a box side at most 1e12 radii for engine ed (R = " + format_value(R) +
                         "): positions of that size are resolved to L·2.2e-16, which must stay far below R");
  // Measured peak memory: about 2.4 kB per disc in 2-D and 4.6 kB per sphere in 3-D (with thermalisation,
  // N = 2e5); the estimate takes 3 and 5 kB.
  const double per_particle = system.box.dimension == 2 ? 3e3 : 5e3;
  check_memory("particles.count", std::to_string(system.count), per_particle * double(system.count),
               "engine ed: about " + memory_text(per_particle) + " per particle");
  const double crossing = R / system.speed;
  if (!(crossing >= 1e-100 && L / system.speed <= 1e100))
    throw InputError("particles.initial.speed", format_value(system.speed),
                     "a speed with R/speed >= 1e-100 and L/speed <= 1e100 for engine ed (its event times are doubles; "
                     "here R/speed = " + format_value(crossing) + ", L/speed = " + format_value(L / system.speed) + ")");
}

ParticleEngineKind::Setup setup_ed(const EngineOptions& given, const Scene& scene) {
  const ParticleSystem& system = *scene.particles;
  check_particles(system);
  Settings settings;
  settings.ed.thermalize = system.thermalize;
  if (given.has("thermalize") && system.thermalize > 0)
    given.fail("thermalize", "thermalize given once: [particles] thermalize = " + std::to_string(system.thermalize) +
                                 " is also set (the engine's key is the one to keep)");
  given.read(ed_option_rows(), settings.ed);
  given.read(stop_rows(), settings);
  check_cluster_stop(given, settings.target_clusters, system.count);
  nlohmann::json values = ed_option_rows().values(settings.ed);
  values.update(stop_rows().values(settings));
  if (settings.ed.elastic) {
    if (settings.target_clusters > 0)
      given.fail("stop", "no cluster target with collisions = \"elastic\" (no clusters form): leave stop out to run to time.end");
    if (given.has("cells"))
      given.fail("cells", "no cells with collisions = \"elastic\" (the hard-sphere gas sizes its own grid): leave cells out");
    return {[system, settings](std::size_t r) {
              return std::make_unique<ElasticGasSimulation>(system, system.initial_state(r), settings.ed);
            },
            "event-driven elastic hard-sphere gas" +
                (settings.ed.thermalize > 0 ? ", after " + std::to_string(settings.ed.thermalize) + " collisions per particle" : std::string()) +
                ", stop at time.end",
            values, {}};
  }
  // Sticking collisions leave no pair virial (the clusters are rigid) and count merges, not collisions.
  if (const auto asked = observable_needing(scene, need::collisions | need::virial))
    throw InputError(asked->first, "\"" + asked->second + "\"",
                     "an observable engine " + given.key("collisions").substr(0, given.key("collisions").rfind('.')) +
                         " (ed) gives only with collisions = \"elastic\"");
  const std::string stop = settings.target_clusters == 0 ? "at time.end"
                                                          : "at " + std::to_string(settings.target_clusters) + " cluster(s)";
  return {[system, settings](std::size_t r) {
            return std::make_unique<EdSimulation>(system, system.initial_state(r), settings);
          },
          "event-driven, stop " + stop, values, {}};
}

}  // namespace

EngineType ed_engine_type() {
  return particle_engine_type({"ed", "event-driven ballistic aggregation of hard discs/spheres ([particles])",
                               ed_options(), setup_ed, need::particles | need::collisions | need::virial});
}

}  // namespace aggkit
