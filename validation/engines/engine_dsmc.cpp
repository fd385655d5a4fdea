// Engine "dsmc": Direct Simulation Monte Carlo of the aggregation-shattering model (particle/dsmc/).
// Options: the table below. Each realisation's state is measured (densities = counts / volume); the
// harness records the mean over the realisations and, with runs > 1, the standard error of each observable
// (series.csv column <name>_stderr).
#include <algorithm>
#include <chrono>
#include <thread>
#include <cmath>
#include <optional>

#include "analysis/input_error.hpp"
#include "particle/common/checkpoint.hpp"
#include "particle/dsmc/ensemble.hpp"
#include "validation/engines/engine.hpp"
#include "validation/engines/rank_share.hpp"
#include "validation/io/machine.hpp"
#include "validation/io/text.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

// One realisation at one time, seen through the harness interface.
class SnapshotState final : public ObservedState {
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

// The statistics of an ensemble over every run (in run order); accepted events per second over `wall`.
EngineStatistics run_summary(const dsmc::Options& options, const std::vector<dsmc::RunStatistics>& run_statistics,
                             std::size_t threads, double wall) {
  dsmc::RunStatistics total;
  std::int64_t extinct = 0, frozen = 0, max_doublings = 0;
  double first_frozen = std::numeric_limits<double>::quiet_NaN();
  for (const dsmc::RunStatistics& s : run_statistics) {
    total.trials += s.trials;
    total.aggregations += s.aggregations;
    total.shatterings += s.shatterings;
    total.leaks += s.leaks;
    total.doublings += s.doublings;
    total.halvings += s.halvings;
    max_doublings = std::max<std::int64_t>(max_doublings, std::int64_t(s.doublings));
    extinct += s.extinct;
    frozen += s.frozen;
    if (s.frozen && !(first_frozen <= s.frozen_time)) first_frozen = s.frozen_time;
  }
  return {
      {"method", dsmc::to_string(options.method)},
      {"particles", std::int64_t(options.particles)},
      {"runs", std::int64_t(options.runs)},
      {"threads", std::int64_t(threads)},
      {"seed", std::to_string(options.seed)},
      {"bucket", std::int64_t(options.bucket)},
      {"truncated", std::string(options.truncate ? "yes" : "no")},
      {"trials", std::int64_t(total.trials)},
      {"accepted_events", std::int64_t(total.accepted())},
      {"aggregations", std::int64_t(total.aggregations)},
      {"shatterings", std::int64_t(total.shatterings)},
      {"leaked_clusters", std::int64_t(total.leaks)},
      {"acceptance_rate", total.trials ? double(total.accepted()) / double(total.trials) : 0.0},
      {"accepted_events_per_second", double(total.accepted()) / wall},
      {"doublings", std::int64_t(total.doublings)},
      {"max_doublings_per_run", max_doublings},
      {"halvings", std::int64_t(total.halvings)},
      {"extinct_runs", extinct},
      {"frozen_runs", frozen},
      {"first_frozen_time", first_frozen},
  };
}

class DsmcEngine final : public Engine {
 public:
  DsmcEngine(std::string label, dsmc::Options options, std::function<std::string(const std::string&)> keys,
             double max_wall_seconds, nlohmann::json settings)
      : Engine("dsmc", std::move(label), std::move(settings)), options_(options), keys_(std::move(keys)), max_wall_seconds_(max_wall_seconds) {}

  std::string describe() const override {
    return dsmc::to_string(options_.method) + ", " + std::to_string(options_.particles) + " particles, " +
           std::to_string(options_.runs) + (options_.runs == 1 ? " run" : " runs") + ", seed " +
           std::to_string(options_.seed) + ", bucket " + std::to_string(options_.bucket) +
           (options_.truncate ? ", truncated" : ", untruncated");
  }

  bool spreads_over_ranks() const override { return true; }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    try {
      return under_key(keys_, [&] { return run_solver(scene, observer); });
    } catch (const CheckpointError& e) {
      throw InputError("--resume", label(), std::string("a checkpoint this engine can continue from; ") + e.what());
    }
  }

 private:
  EngineStatistics run_solver(const Scene& scene, const EngineObserver& observer) const {
    const auto started = std::chrono::steady_clock::now();
    // With several ranks (rank_share.hpp) each advances its share of the runs, and rank 0 records the
    // measurements of every run in run order at each output time; checkpoints are then off (the harness
    // refuses them). The other ranks return with nothing.
    const RankGroup* ranks = shared_ranks(observer.ranks);
    const bool records = !ranks || ranks->rank() == 0;
    const std::vector<std::size_t> mine = realizations_of_rank(options_.runs, ranks);
    std::optional<dsmc::Ensemble> ensemble;
    gather_shares(ranks, [&] {
      ensemble.emplace(scene.model, options_, scene.time.end, mine);
      return std::string();
    });
    // Progress between output times (run 0, on this thread of rank 0) and the wall-time budget (every run).
    double last_note = -1;
    const auto every = [&](std::size_t run, double time) {
      const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      if (max_wall_seconds_ > 0 && spent > max_wall_seconds_)
        throw std::runtime_error("stopped: the wall-time budget of " + shortest_text(max_wall_seconds_) +
                                 " s (engine option max_wall_seconds) ran out at t = " + shortest_text(time));
      if (mine[run] == 0 && observer.status && spent - last_note >= 1.0) {
        last_note = spent;
        observer.status("t = " + shortest_text(time) + " of " + shortest_text(scene.time.end));
      }
    };
    // Checkpoints: after output k, the number of outputs done and every realisation's state.
    const std::vector<double>& outputs = scene.time.outputs;
    std::uint64_t first = 0;
    if (observer.checkpoint && !observer.checkpoint->resumed().empty()) {
      StateReader in(observer.checkpoint->resumed());
      in.get(first);
      ensemble->restore(in);
      in.expect_end();
      if (first > outputs.size()) throw CheckpointError("the checkpoint has more outputs than this scene");
    }
    for (std::uint64_t k = first; k < outputs.size(); ++k) {
      const double t = outputs[k];
      const auto measured = [&] {  // this rank's runs at t
        std::vector<Measurement> runs;
        for (auto& snapshot : ensemble->advance_to(t, every))
          runs.push_back(observer.measure(t, SnapshotState(std::move(snapshot), scene.model.size)));
        return runs;
      };
      std::vector<Measurement> runs = gather_realization_values<Measurement>(
          ranks, options_.runs, [&](const std::vector<std::size_t>&) { return measured(); }, put_measurement,
          get_measurement);
      if (!records) continue;
      observer.record(t, std::move(runs));
      if (observer.progress) observer.progress(t);
      if (observer.checkpoint && observer.checkpoint->due()) {
        StateWriter out;
        out.put(k + 1);
        ensemble->save(out);
        observer.checkpoint->save(out.take());
      }
    }
    // The statistics of every run, in run order, on rank 0.
    const std::vector<dsmc::RunStatistics> run_statistics = gather_realization_values<dsmc::RunStatistics>(
        ranks, options_.runs,
        [&](const std::vector<std::size_t>&) {
          std::vector<dsmc::RunStatistics> own;
          for (std::size_t i = 0; i < ensemble->runs(); ++i) own.push_back(ensemble->run(i).statistics());
          return own;
        },
        [](StateWriter& out, const dsmc::RunStatistics& s) { out.put(s); },
        [](StateReader& in) { return in.read<dsmc::RunStatistics>(); });
    if (!records) return {};
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    EngineStatistics statistics = run_summary(options_, run_statistics, ensemble->threads(), wall);
    if (ranks) statistics.push_back({"ranks", std::int64_t(ranks->size())});  // threads: those of rank 0
    if (first > 0) statistics.push_back({"resumed_at", outputs[first - 1]});  // a resume: the output it continued from
    return statistics;
  }

  dsmc::Options options_;
  std::function<std::string(const std::string&)> keys_;  // solver parameter -> scene key
  double max_wall_seconds_;
};

// What the harness adds to a DSMC run.
struct Budget {
  double max_wall_seconds = 0;  // 0: none
};

const OptionRows<Budget>& budget_rows() {
  static const OptionRows<Budget> rows{{
      Bind<Budget>::number("max_wall_seconds", &Budget::max_wall_seconds, closed(0.0, 1e9),
                           "wall-time budget of the whole ensemble; the run fails when it is spent (0: none)"),
  }};
  return rows;
}

const OptionTable& dsmc_options() {
  static const OptionTable table = option_table(dsmc::option_rows(), budget_rows());
  return table;
}

// What a run would cost, refused before it starts when it cannot finish: memory (each concurrent run holds
// at most about 3 N(0) clusters after shattering refills the population, some 16 bytes each, plus its
// per-size buckets) and events. The collision rate of a run starts at ½ N(0) n(0) K_max (1 + λ) [Kalinov2022,
// eqs. 6-7]; population control keeps N >= N(0)/2, so with shattering the rate stays of that order:
// ½ N(0) n(0) K(1,1) (1 + λ_max) t_end events per run is the estimate (an upper bound without shattering).
void check_resources(const EngineOptions& given, const dsmc::Options& options, const Scene& scene) {
  const double runs = double(options.runs);
  const std::size_t threads = options.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : options.threads;
  const double concurrent = std::min(runs, double(threads));
  const double bytes = concurrent * (48.0 * double(options.particles) + 16.0 * double(options.bucket));
  check_memory(given.key("particles"), std::to_string(options.particles), bytes,
               "about 48 bytes per particle and 16 per bucket, for " + std::to_string(std::size_t(concurrent)) + " concurrent runs");
  const AggregationModel& model = scene.model;
  double lambda_max = 0;
  for (int i = 0; i <= 100; ++i) lambda_max = std::max(lambda_max, model.lambda(scene.time.end * i / 100.0));
  double density = 0;
  for (double n : model.initial) density += n;
  const double events = 0.5 * double(options.particles) * density * model.kernel(1, 1) * (1 + lambda_max) * scene.time.end * runs;
  constexpr double max_events = 1e13;  // about a day at 1e8 events/s
  if (!(events <= max_events))
    throw InputError(given.key("particles"), std::to_string(options.particles),
                     "a run that can finish: with runs = " + std::to_string(options.runs) + ", lambda up to " +
                         shortest_text(lambda_max) + " and time.end = " + shortest_text(scene.time.end) + " it needs about " +
                         shortest_text(events) + " collision events (at most 1e13, about a day): fewer particles or runs, "
                         "a smaller lambda or an earlier end");
}

std::unique_ptr<Engine> build_dsmc(const EngineOptions& given, const EngineSpec& spec, const Scene& scene) {
  const auto rekey = [&given](const std::string& parameter) { return given.key(leaf_key(parameter)); };
  dsmc::Options options;
  given.read(dsmc::option_rows(), options);
  Budget budget;
  given.read(budget_rows(), budget);
  under_key(rekey, [&] { options.validate(); });  // the model (λ >= 0, N, start) is validated with the scene
  check_resources(given, options, scene);
  nlohmann::json settings = dsmc::option_rows().values(options);
  settings.update(budget_rows().values(budget));
  return std::make_unique<DsmcEngine>(spec.label, options, solver_keys(spec, dsmc_options()), budget.max_wall_seconds,
                                      std::move(settings));
}

}  // namespace

EngineType dsmc_engine_type() {
  return {"dsmc", "Direct Simulation Monte Carlo (acceptance-rejection or fast DSMC), ensembles with standard errors",
          dsmc_options(), need::kinetic, true, {}, build_dsmc};
}

}  // namespace aggkit
