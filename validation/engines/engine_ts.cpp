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

namespace aggkit {

namespace {

const OptionTable& ts_options() {
  static const OptionTable table{
      number_option("dt_factor", "0.01", "Δt(0) = dt_factor · L / max|V(0)|, growing to 2Δt(0) at one cluster [Degond2024, Table 1]",
                    0.0, 1.0, true),
      cluster_stop_option(),
      number_option("c_bar", "2", "damping c̄ of the DAHA (c = δ c̄ per iteration, at most 1/δ)", 0.0, 1e6, true),
      number_option("delta", "0.15", "DAHA step δ", 0.0, 10.0, true),
      number_option("alpha", "0.3", "DAHA force coefficient α (attraction and multipliers)", 0.0, 1e6, true),
      number_option("gamma", "1", "DAHA coefficient γ of the φλ∇φ term", 0.0, 1e6),
      number_option("beta_bar", "1.5", "multiplier rate β̄ (β = δ β̄)", 0.0, 1e6, true),
      number_option("eps_c", "0.01", "ε_c: mean √|φ| over the links at convergence (paper units, R = 0.2)", 0.0, 1.0, true),
      number_option("eps_s", "0.001", "ε_s: largest move of a sphere in the last iteration (paper units, R = 0.2)", 0.0, 1.0, true),
      number_option("interaction_range", "4", "Δ_W / R: links attract only within Δ_W; free spheres lie within Δ_W of a new link", 2.0,
                    1e6),
      flag_option("contact_time", true, "merge a binary collision at its contact time (rewound along the flight, merged, flown on); "
                                        "false: every contact resolved from its end-of-flight overlap by the DAHA, as [Degond2024]"),
      number_option("substep_displacement", "0.25", "largest flight of a cluster in one substep, in diameters 2R: a longer step is "
                    "flown in substeps, each followed by contact detection along the flown paths", 0.0, 1e6, true),
      integer_option("max_iterations", "100000", "iteration cap of one minimisation (hits are counted)", 1, 1e9),
      word_option("variant", "local", "local: almost rigid clusters [Degond2024, Sec. 3.3]; global: every sphere of the clusters touched "
                                      "moves, all their pairs constrained (Sec. 3.1, O(n²))",
                  {"local", "global"}),
      integer_option("cluster_threads", "1", "workers for the minimisations of separate clusters in one step (results do not depend on it)",
                     1, 4096),
  };
  return table;
}

struct Settings {
  TsSettings ts;
  std::size_t target_clusters = 0;  // 0: stop at time.end
};

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
  settings.target_clusters = cluster_stop_target(given, system.count);
  TsSettings& ts = settings.ts;
  ts.dt_factor = given.number("dt_factor", ts.dt_factor);
  ts.daha.c_bar = given.number("c_bar", ts.daha.c_bar);
  ts.daha.delta = given.number("delta", ts.daha.delta);
  ts.daha.alpha = given.number("alpha", ts.daha.alpha);
  ts.daha.gamma = given.number("gamma", ts.daha.gamma);
  ts.daha.beta_bar = given.number("beta_bar", ts.daha.beta_bar);
  ts.daha.eps_c = given.number("eps_c", ts.daha.eps_c);
  ts.daha.eps_s = given.number("eps_s", ts.daha.eps_s);
  ts.daha.max_iterations = std::size_t(given.integer("max_iterations", std::int64_t(ts.daha.max_iterations)));
  ts.interaction_range = given.number("interaction_range", ts.interaction_range);
  ts.substep_displacement = given.number("substep_displacement", ts.substep_displacement);
  ts.contact_time = given.boolean("contact_time", ts.contact_time);
  ts.global = given.word("variant", "local") == "global";
  ts.threads = std::size_t(given.integer("cluster_threads", 1));
  if (ts.daha.delta * ts.daha.c_bar > 1.0)
    given.fail("c_bar", "c_bar <= 1/delta = " + format_value(1.0 / ts.daha.delta) + " (the damping δ c̄ of one iteration is at most 1)");
  const std::string stop = settings.target_clusters == 0 ? "at time.end" : "at " + std::to_string(settings.target_clusters) + " cluster(s)";
  return {[system, settings](std::size_t r) { return std::make_unique<TsSimulation>(system, system.initial_state(r), settings); },
          "time-stepping (" + std::string(ts.global ? "global" : "local") + " DAHA, dt_factor " + format_value(ts.dt_factor) +
              "), stop " + stop};
}

}  // namespace

EngineType ts_engine_type() {
  return particle_engine_type({"ts", "time-stepping ballistic aggregation of hard discs/spheres, DAHA minimisation ([particles])",
                               ts_options(), setup_ts});
}

}  // namespace aggkit
