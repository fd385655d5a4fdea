// Engine "ed": event-driven ballistic aggregation of the scene's [particles] (particle/ed/). Option:
//   stop = "one_cluster" | { clusters = K }    run until that many clusters remain (beyond time.end if
//                                              needed); absent: stop at time.end
//   cells = 0                                  wanted number of cells (0: about one per particle)
// Outputs: the series at the output times (a realization that has stopped holds its final state for the
// later output times — exact for "one_cluster": nothing changes any more but the position), averaged over
// the realizations; <label>/final.json with the requested observe.final values plus events, wall_seconds,
// momentum_drift and stop_time (means; with several realizations also <name>_stderr), and with
// particles.thermalize the collisions of the elastic stage (run on particle/ed/elastic_gas.hpp, after which
// the clock restarts at 0) as thermalization_collisions; the requested profiles (pair_distribution) as
// <label>/<name>.csv; and with
// observe.snapshots the first realization's final configuration as final.vtu and final.png.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include "analysis/particle_configuration.hpp"
#include "particle/ed/ed_configuration.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/observables/particle_final_state.hpp"
#include "validation/io/particle_snapshot.hpp"
#include "validation/observables/particle_state.hpp"
#include "validation/scene/scene.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

struct EdOptions {
  std::size_t target_clusters = 0;  // 0: stop at time.end
  std::size_t cells = 0;
};

ParticleState state_of(const EventDrivenAggregation& ed) {
  const std::vector<std::size_t> sizes = ed.cluster_sizes();
  return ParticleState(sizes, ed.kinetic_energy());
}

// Mean and standard error of the mean of each key over the realizations.
class FinalAverages {
 public:
  void add(const std::string& key, double value) {
    auto& [order, values] = entries_[key];
    if (values.empty()) order = entries_.size();
    values.push_back(value);
  }
  std::string json(std::size_t realizations) const {
    std::vector<std::pair<std::size_t, std::string>> keys;
    for (const auto& [key, entry] : entries_) keys.emplace_back(entry.first, key);
    std::sort(keys.begin(), keys.end());
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    const auto number = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr); };
    for (const auto& [order, key] : keys) {
      const std::vector<double>& v = entries_.at(key).second;
      double mean = 0;
      for (double x : v) mean += x / double(v.size());
      out[key] = number(mean);
      if (realizations > 1) {
        double variance = 0;
        for (double x : v) variance += (x - mean) * (x - mean) / double(v.size() - 1);
        out[key + "_stderr"] = number(std::sqrt(variance / double(v.size())));
      }
    }
    out["realizations"] = realizations;
    return out.dump(2) + "\n";
  }

 private:
  std::map<std::string, std::pair<std::size_t, std::vector<double>>> entries_;
};

class EdEngine final : public Engine {
 public:
  EdEngine(std::string label, EdOptions options) : Engine("ed", std::move(label)), options_(options) {}

  std::string describe() const override {
    return "event-driven, stop " + (options_.target_clusters == 0 ? std::string("at time.end")
                                                                   : "at " + std::to_string(options_.target_clusters) + " cluster(s)");
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    const ParticleSystem& system = *scene.particles;
    const std::vector<double>& outputs = scene.time.outputs;
    std::vector<ParticleState> states(outputs.size());
    FinalAverages final_values;
    std::vector<std::vector<FinalProfile>> profiles;  // per realization
    EdCounters total;
    std::string picture = "not requested";
    for (std::size_t r = 0; r < system.realizations; ++r) {
      const auto started = std::chrono::steady_clock::now();
      const std::vector<Vector3> x = system.initial_positions(), v = system.initial_velocities(r);
      EventDrivenAggregation ed(system.box, system.mean_radius(), x, v, true, options_.cells);
      // Progress in words for the long stretches between output times (at most about once a second).
      const std::string run = system.realizations > 1 ? "realization " + std::to_string(r + 1) + "/" +
                                                            std::to_string(system.realizations) + ", "
                                                      : "";
      const auto thermalizing = [&](std::size_t pending) {
        if (observer.status)
          observer.status(run + "thermalising: " + std::to_string(ed.particles() - pending) + " of " +
                          std::to_string(ed.particles()) + " particles have " + std::to_string(system.thermalize) +
                          " collisions");
      };
      const auto aggregating = [&] {
        if (!observer.status) return;
        char t[32];
        std::snprintf(t, sizeof t, "%.6g", ed.time());
        observer.status(run + "t = " + t + ", " + std::to_string(ed.clusters()) + " clusters");
      };
      ed.thermalize(system.thermalize, thermalizing);  // on the elastic gas; the clock restarts at 0
      const double thermal_collisions = double(ed.counters().elastic_collisions);
      const Vector3 p0 = ed.momentum() + ed.wall_impulse();
      double momentum_scale = 0;
      for (std::uint32_t p = 0; p < ed.particles(); ++p) momentum_scale += norm(ed.velocity(p));
      bool stopped = false;
      for (std::size_t k = 0; k < outputs.size(); ++k) {
        if (!stopped) stopped = ed.advance(outputs[k], options_.target_clusters, aggregating) == EdStop::clusters_reached;
        states[k] += state_of(ed);
        if (r == 0 && observer.progress) observer.progress(outputs[k]);
      }
      run_to_target(ed, stopped, scene.time.end, aggregating);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

      const ParticleConfiguration config = configuration(ed);
      const std::vector<std::uint32_t> labels = ed.cluster_labels();
      const std::vector<Vector3> largest = ed.cluster_positions(ed.largest_cluster());
      const FinalConfiguration final{config, labels, largest, ed.kinetic_energy()};
      for (const auto& [key, value] : final_state_values(scene.observe.final_state, final)) final_values.add(key, value);
      profiles.push_back(final_profiles(scene.observe.final_state, final));
      final_values.add("events", double(ed.counters().events()));
      if (system.thermalize > 0) final_values.add("thermalization_collisions", thermal_collisions);
      final_values.add("wall_seconds", wall);
      final_values.add("momentum_drift", norm(ed.momentum() + ed.wall_impulse() - p0) / momentum_scale);
      final_values.add("stop_time", ed.time());
      accumulate(total, ed.counters());
      if (r == 0 && scene.observe.snapshots) {
        const std::vector<Vector3> velocities = ed.velocities();
        write_vtu_snapshot(observer.folder / "final.vtu", config, labels, velocities);
        std::string error;
        picture = write_cluster_picture(observer.folder / "final.png", config, labels, &error) ? "final.png"
                                                                                                : "failed: " + error;
      }
    }
    for (std::size_t k = 0; k < outputs.size(); ++k) {
      states[k] *= 1.0 / double(system.realizations);
      observer.output(outputs[k], states[k]);
    }
    write_file_atomically(observer.folder / "final.json", final_values.json(system.realizations));
    write_final_profiles(observer.folder, profiles);
    return {
        {"particles", system.describe()},
        {"realizations", std::int64_t(system.realizations)},
        {"events", std::int64_t(total.events())},
        {"merges", std::int64_t(total.merges)},
        {"elastic_collisions", std::int64_t(total.elastic_collisions)},
        {"cell_crossings", std::int64_t(total.cell_crossings)},
        {"wall_contacts", std::int64_t(total.wall_contacts)},
        {"stale_events", std::int64_t(total.stale_events)},
        {"picture", picture},
    };
  }

 private:
  static void accumulate(EdCounters& total, const EdCounters& c) {
    total.merges += c.merges;
    total.elastic_collisions += c.elastic_collisions;
    total.cell_crossings += c.cell_crossings;
    total.wall_contacts += c.wall_contacts;
    total.stale_events += c.stale_events;
  }

  // With a cluster target not reached by time.end, runs on in chunks of time.end until it is, or until
  // no event remains (nothing will ever change: the engine's events can be far apart, so a quiet chunk alone
  // proves nothing).
  void run_to_target(EventDrivenAggregation& ed, bool stopped, double chunk, const std::function<void()>& progress) const {
    if (stopped || options_.target_clusters == 0) return;
    while (ed.clusters() > options_.target_clusters) {
      const auto before = ed.counters().events();
      if (ed.advance(ed.time() + chunk, options_.target_clusters, progress) == EdStop::clusters_reached) return;
      if (ed.counters().events() == before && ed.exhausted()) return;
    }
  }

  EdOptions options_;
};

std::unique_ptr<Engine> parse_ed(const SceneTable& table, std::string label, const Scene& scene) {
  if (!scene.particles) table.fail("name", "a scene with a [particles] section (engine ed simulates particles)");
  EdOptions options;
  if (const toml::node* stop = table.find("stop")) {
    const std::string forms = "\"one_cluster\" or { clusters = K } with 1 <= K <= particles.count";
    if (stop->is_string()) {
      if (table.string("stop") != "one_cluster") table.fail("stop", forms);
      options.target_clusters = 1;
    } else if (stop->is_table()) {
      const SceneTable rule = table.table("stop");
      rule.allow_only({"clusters"});
      options.target_clusters = rule.count("clusters", 1);
      if (options.target_clusters > scene.particles->count) rule.fail("clusters", forms);
    } else {
      table.fail("stop", forms);
    }
  }
  options.cells = table.optional_count("cells", 0).value_or(0);
  return std::make_unique<EdEngine>(std::move(label), options);
}

}  // namespace

EngineType ed_engine_type() {
  return {"ed", "event-driven ballistic aggregation of hard discs/spheres ([particles])", {"stop", "cells"}, parse_ed,
          /*needs_model=*/false};
}

}  // namespace aggkit
