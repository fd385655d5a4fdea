// Engine "ts": time-stepping ballistic aggregation of the scene's [particles] (particle/ts/): the same
// physics as engine ed (equal hard discs or spheres sticking into rigid clusters that translate with the
// momentum-weighted velocity), advanced in steps of Δt whose contacts are resolved together by the damped
// Arrow–Hurwicz minimisation [Degond2024, Sec. 3]. Everything an ensemble shares comes from the particle
// runner; this file is the engine's options and one realization. The runner's `threads` runs realizations
// at once; `cluster_threads` runs the minimisations of separate clusters within one realization at once.
// final.json gains steps, minimisation_iterations, iteration_cap_hits, max_overlap and mean_overlap
// (√φ⁺ of eq. 3.28 in the paper's units, R = 0.2, comparable with eps_c).
#include <algorithm>
#include <cstdio>

#include "analysis/input_error.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"
#include "particle/common/box_configuration.hpp"
#include "validation/engines/particle_runner.hpp"
#include "validation/engines/sticky_spheres.hpp"
#include "validation/io/machine.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

struct Settings {
  TsSettings ts;
  std::size_t target_clusters = 0;  // 0: stop at time.end
};

const OptionRows<Settings>& stop_rows() {
  static const OptionRows<Settings> rows{{cluster_stop_row(&Settings::target_clusters)}};
  return rows;
}

const OptionTable& ts_options() {
  static const OptionTable table = [] {
    OptionTable t = option_table(ts_option_rows(), stop_rows());
    std::rotate(t.begin() + 1, t.end() - 1, t.end());  // stop after dt_factor, as --help has always listed it
    return t;
  }();
  return table;
}

class TsSimulation final : public ParticleSimulation {
 public:
  TsSimulation(const ParticleSystem& system, const ParticleStart& start, const Settings& settings)
      : ts_(system.box, system.mean_radius(), start.positions, start.velocities, settings.ts),
        target_(settings.target_clusters),
        mass_(system.mean_mass()) {}

  bool advance(double t, const StatusSink& status) override {
    return ts_.advance(t, target_, [&] { report(status); }) == TsStop::clusters_reached;
  }

  // A cluster target not reached by time.end: runs on until it is, or until no cluster moves relative to
  // another (nothing can change any more); the runner's wall-time budget is checked at every report.
  void finish(double end, const StatusSink& status) override {
    if (target_ == 0) return;
    double chunk = std::max(end, ts_.time_step());
    while (ts_.clusters() > target_ && !ts_.at_rest()) {
      if (ts_.advance(ts_.time() + chunk, target_, [&] { report(status); }) == TsStop::clusters_reached) return;
      report(status);
      chunk *= 2;
    }
  }

  double time() const override { return ts_.time(); }
  ParticleConfiguration configuration() const override {
    return configuration_in(ts_.box(), ts_.radius(), ts_.positions());
  }
  std::vector<Vector3> velocities() const override { return ts_.velocities(); }
  std::vector<double> masses() const override { return std::vector<double>(ts_.particles(), mass_); }
  std::vector<std::uint32_t> cluster_labels() const override { return ts_.cluster_labels(); }
  std::vector<Vector3> largest_cluster() const override { return ts_.cluster_positions(ts_.largest_cluster()); }
  double kinetic_energy() const override { return mass_ * ts_.kinetic_energy(); }
  Vector3 momentum() const override { return mass_ * ts_.momentum(); }
  Vector3 wall_impulse() const override { return mass_ * ts_.wall_impulse(); }

  std::vector<std::pair<std::string, double>> final_values() const override {
    const TsCounters& c = ts_.counters();
    return {{"steps", double(c.steps)},
            {"minimisation_iterations", double(c.minimisation_iterations)},
            {"iteration_cap_hits", double(c.iteration_cap_hits)},
            {"max_overlap", ts_.largest_overlap()},
            {"mean_overlap", c.minimisations ? c.overlap_sum / double(c.minimisations) : 0.0}};
  }
  bool saves_state() const override { return true; }
  void save(StateWriter& out) const override { ts_.save(out); }
  void restore(StateReader& in) override { ts_.restore(in); }
  std::vector<std::pair<std::string, std::int64_t>> counters() const override {
    const TsCounters& c = ts_.counters();
    return {{"steps", std::int64_t(c.steps)},
            {"substeps", std::int64_t(c.substeps)},
            {"secondary_merges", std::int64_t(c.secondary_merges)},
            {"contact_time_merges", std::int64_t(c.contact_time_merges)},
            {"merges", std::int64_t(c.merges)},
            {"minimisations", std::int64_t(c.minimisations)},
            {"minimisation_iterations", std::int64_t(c.minimisation_iterations)},
            {"iteration_cap_hits", std::int64_t(c.iteration_cap_hits)},
            {"link_rounds", std::int64_t(c.rounds)},
            {"round_cap_hits", std::int64_t(c.round_cap_hits)},
            {"free_spheres", std::int64_t(c.free_spheres)},
            {"wall_contacts", std::int64_t(c.wall_contacts)}};
  }

 private:
  void report(const StatusSink& status) const {
    char t[32];
    std::snprintf(t, sizeof t, "%.6g", ts_.time());
    status("t = " + std::string(t) + ", " + std::to_string(ts_.clusters()) + " clusters, " +
           std::to_string(ts_.counters().steps) + " steps");
  }

  TimeSteppingAggregation ts_;
  std::size_t target_;
  double mass_;
};

// The forms of [particles] this engine cannot use are refused, naming the key (as engine ed).
void check_particles(const ParticleSystem& system) {
  require_sticky_spheres(system, "ts", "its step law needs a box side L", "Δt = dt_factor L / max|V|");
  // Measured peak memory well under 1 kB per particle (positions, cells, links); the estimate takes 1 kB.
  check_memory("particles.count", std::to_string(system.count), 1e3 * double(system.count), "engine ts: about 1 kB per particle");
}

ParticleEngineKind::Setup setup_ts(const EngineOptions& given, const Scene& scene) {
  const ParticleSystem& system = *scene.particles;
  check_particles(system);
  Settings settings;
  given.read(ts_option_rows(), settings.ts);
  given.read(stop_rows(), settings);
  check_cluster_stop(given, settings.target_clusters, system.count);
  const auto rekey = [&given](const std::string& parameter) { return given.key(parameter); };
  under_key(rekey, [&] { settings.ts.validate(); });
  const TsSettings& ts = settings.ts;
  nlohmann::json values = ts_option_rows().values(ts);
  values.update(stop_rows().values(settings));
  const std::string stop = settings.target_clusters == 0 ? "at time.end" : "at " + std::to_string(settings.target_clusters) + " cluster(s)";
  return {[system, settings](std::size_t r) { return std::make_unique<TsSimulation>(system, system.initial_state(r), settings); },
          "time-stepping (" + std::string(ts.global ? "global" : "local") + " DAHA, dt_factor " + format_value(ts.dt_factor) +
              "), stop " + stop,
          values, {}};
}

}  // namespace

EngineType ts_engine_type() {
  return particle_engine_type({"ts", "time-stepping ballistic aggregation of hard discs/spheres, DAHA minimisation ([particles])",
                               ts_options(), setup_ts});
}

}  // namespace aggkit
