// Engine "dsmc": Direct Simulation Monte Carlo of the aggregation-shattering model (particle/dsmc/).
// Options: method (ar | fast), particles (N(0) >= 2), seed (master seed), runs (independent realisations,
// run in threads), bucket (B >= 1: sizes <= B grouped in buckets), truncate (bool: apply model.size and
// model.truncation; default false = the untruncated system), population_control (bool, default true),
// threads (0 = all cores). Observables are those of the ensemble mean (densities = counts / volume); with
// runs > 1 each also gets a standard error (series.csv column <name>_stderr).
#include <chrono>
#include <cmath>

#include "particle/dsmc/ensemble.hpp"
#include "validation/scene/scene.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

// One realisation at one time, seen through the harness interface.
class SnapshotState final : public SystemState {
 public:
  SnapshotState(dsmc::Snapshot snapshot, std::size_t size) : snapshot_(std::move(snapshot)), size_(size) {}
  double moment(double p) const override { return snapshot_.moment(p); }
  double density(std::size_t k) const override { return snapshot_.density(k); }
  double leaked_mass() const override { return snapshot_.leaked_density(); }
  std::vector<double> distribution() const override {  // n_1..n_N of the model's size range
    std::vector<double> n(size_, 0.0);
    for (const auto& [size, count] : snapshot_.groups)
      if (size <= size_) n[size - 1] = double(count) / snapshot_.volume;
    return n;
  }

 private:
  dsmc::Snapshot snapshot_;
  std::size_t size_;
};

// The mean of independent realisations; each one stays available for standard errors.
class EnsembleState final : public SystemState {
 public:
  explicit EnsembleState(std::vector<SnapshotState> runs) : runs_(std::move(runs)) {}
  double moment(double p) const override { return mean([p](const SystemState& s) { return s.moment(p); }); }
  double density(std::size_t k) const override { return mean([k](const SystemState& s) { return s.density(k); }); }
  double leaked_mass() const override { return mean([](const SystemState& s) { return s.leaked_mass(); }); }
  std::vector<double> distribution() const override {
    std::vector<double> n = runs_.front().distribution();
    for (std::size_t r = 1; r < runs_.size(); ++r) {
      const std::vector<double> m = runs_[r].distribution();
      for (std::size_t k = 0; k < n.size(); ++k) n[k] += m[k];
    }
    for (double& x : n) x /= double(runs_.size());
    return n;
  }
  std::size_t realisations() const override { return runs_.size(); }
  const SystemState& realisation(std::size_t r) const override { return runs_[r]; }

 private:
  template <class F>
  double mean(F f) const {
    double sum = 0.0;
    for (const auto& run : runs_) sum += f(run);
    return sum / double(runs_.size());
  }
  std::vector<SnapshotState> runs_;
};

class DsmcEngine final : public Engine {
 public:
  DsmcEngine(std::string label, dsmc::Options options) : Engine("dsmc", std::move(label)), options_(options) {}

  std::string describe() const override {
    return dsmc::to_string(options_.method) + ", " + std::to_string(options_.particles) + " particles, " +
           std::to_string(options_.runs) + (options_.runs == 1 ? " run" : " runs") + ", seed " +
           std::to_string(options_.seed) + ", bucket " + std::to_string(options_.bucket) +
           (options_.truncate ? ", truncated" : ", untruncated");
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    const auto started = std::chrono::steady_clock::now();
    dsmc::Ensemble ensemble(scene.model, options_, scene.time.end);
    for (double t : scene.time.outputs) {
      std::vector<SnapshotState> runs;
      for (auto& snapshot : ensemble.advance_to(t)) runs.emplace_back(std::move(snapshot), scene.model.size);
      observer.output(t, EnsembleState(std::move(runs)));
      if (observer.progress) observer.progress(t);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    dsmc::RunStatistics total;
    std::int64_t extinct = 0, frozen = 0, max_doublings = 0;
    double first_frozen = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t r = 0; r < ensemble.runs(); ++r) {
      const auto& s = ensemble.run(r).statistics();
      total.trials += s.trials;
      total.aggregations += s.aggregations;
      total.shatterings += s.shatterings;
      total.leaks += s.leaks;
      total.doublings += s.doublings;
      max_doublings = std::max<std::int64_t>(max_doublings, std::int64_t(s.doublings));
      extinct += s.extinct;
      frozen += s.frozen;
      if (s.frozen && !(first_frozen <= s.frozen_time)) first_frozen = s.frozen_time;
    }
    return {
        {"method", dsmc::to_string(options_.method)},
        {"particles", std::int64_t(options_.particles)},
        {"runs", std::int64_t(options_.runs)},
        {"threads", std::int64_t(ensemble.threads())},
        {"seed", std::to_string(options_.seed)},
        {"bucket", std::int64_t(options_.bucket)},
        {"truncated", std::string(options_.truncate ? "yes" : "no")},
        {"trials", std::int64_t(total.trials)},
        {"accepted_events", std::int64_t(total.accepted())},
        {"aggregations", std::int64_t(total.aggregations)},
        {"shatterings", std::int64_t(total.shatterings)},
        {"leaked_clusters", std::int64_t(total.leaks)},
        {"acceptance_rate", total.trials ? double(total.accepted()) / double(total.trials) : 0.0},
        {"accepted_events_per_second", double(total.accepted()) / wall},
        {"doublings", std::int64_t(total.doublings)},
        {"max_doublings_per_run", max_doublings},
        {"extinct_runs", extinct},
        {"frozen_runs", frozen},
        {"first_frozen_time", first_frozen},
    };
  }

 private:
  dsmc::Options options_;
};

std::unique_ptr<Engine> parse_dsmc(const SceneTable& table, std::string label, const Scene& scene) {
  const auto rekey = [&table](const std::string& library_key) { return table.key(leaf_key(library_key)); };
  dsmc::Options options;
  if (const auto method = table.optional_string("method"))
    options.method = under_key(rekey, [&] { return dsmc::method_from_name(*method); });
  options.particles = table.optional_count("particles", 0).value_or(options.particles);
  options.seed = table.optional_count("seed", 0).value_or(options.seed);
  options.runs = table.optional_count("runs", 0).value_or(options.runs);
  options.bucket = table.optional_count("bucket", 0).value_or(options.bucket);
  options.truncate = table.optional_boolean("truncate").value_or(options.truncate);
  options.population_control = table.optional_boolean("population_control").value_or(options.population_control);
  options.threads = table.optional_count("threads", 0).value_or(options.threads);
  under_key(rekey, [&] { options.validate(); });
  (void)scene;  // the model (λ >= 0, N, start) is validated with the scene
  return std::make_unique<DsmcEngine>(std::move(label), options);
}

}  // namespace

EngineType dsmc_engine_type() {
  return {"dsmc",
          "Direct Simulation Monte Carlo (acceptance-rejection or fast DSMC), ensembles with standard errors",
          {"method", "particles", "seed", "runs", "bucket", "truncate", "population_control", "threads"},
          parse_dsmc};
}

}  // namespace aggkit
