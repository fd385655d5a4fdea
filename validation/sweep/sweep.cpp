#include "validation/sweep/sweep.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <streambuf>

#include "validation/harness/harness.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"
#include "validation/io/text.hpp"
#include "validation/runs/run_store.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/sweep/sweep_record.hpp"

namespace aggkit {

namespace {

// A stream that writes each line to `out` behind a prefix: the harness's progress lines of a run, marked with
// the rank and the point ("aggkit sweep: [rank 1] point 3, realization 0: aggkit: engine 1/1 dem: t = 4 / 20").
class PrefixedLines : public std::streambuf {
 public:
  PrefixedLines(std::ostream& out, std::string prefix) : out_(out), prefix_(std::move(prefix)) {}

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    line_ += char(c);
    if (c == '\n') sync();
    return c;
  }
  int sync() override {
    if (!line_.empty()) out_ << prefix_ << line_ << std::flush;
    line_.clear();
    return 0;
  }

 private:
  std::ostream& out_;
  std::string prefix_, line_;
};

std::string run_name(std::size_t point, std::size_t realization) {
  return "point" + std::to_string(point) + "_r" + std::to_string(realization);
}

std::string point_words(const SweepPlan& plan, std::size_t point, std::size_t realization) {
  std::string words;
  const auto values = plan.point(point);
  for (std::size_t a = 0; a < plan.axes.size(); ++a)
    words += (a ? ", " : "") + plan.axes[a].key + " = " + sweep_value_text(values[a]);
  if (plan.realizations > 1) words += ", realization " + std::to_string(realization);
  return words;
}

// The final values of one run: each engine's final.json entries, then its series at the last output time
// (those not among them); "<label>." before each name when the scene has several engines. A particle
// engine's "wall_seconds" is how long the run took, not a result: it goes to timing.csv (the run's seconds),
// never into sweep.csv, whose bytes a rerun or a resumed sweep reproduces.
std::vector<std::pair<std::string, double>> final_columns(const Scene& scene, const RunResult& result) {
  std::vector<std::pair<std::string, double>> columns;
  const bool prefixed = result.records.size() > 1;
  for (const EngineRecord& record : result.records) {
    const std::string prefix = prefixed ? record.label + "." : "";
    std::vector<std::string> names;
    for (const FinalStatistic& f : record.finals) {
      if (f.name == "wall_seconds") continue;
      columns.emplace_back(prefix + f.name, f.mean);
      names.push_back(f.name);
    }
    if (record.values.empty()) continue;
    for (std::size_t j = 0; j < scene.observe.series.size(); ++j) {
      const std::string& name = scene.observe.series[j].name();
      if (std::find(names.begin(), names.end(), name) == names.end()) columns.emplace_back(prefix + name, record.values.back()[j]);
    }
  }
  return columns;
}

std::filesystem::path plot_sweep_script() {
  return plot_script("AGGKIT_PLOT_SWEEP_SCRIPT", AGGKIT_PLOT_SWEEP_SCRIPT_BUILD, AGGKIT_PLOT_SWEEP_SCRIPT_INSTALL);
}

// A column name as part of a file name: letters, digits, '.', '-' and '_' kept, anything else '_'.
std::string file_word(const std::string& name) {
  std::string word = name;
  for (char& c : word)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return word;
}

// The file word of a grouping: its keys joined by "__".
std::string grouping_word(const SweepPlan& plan, const std::vector<std::size_t>& grouping) {
  std::string word;
  for (std::size_t a : grouping) word += (word.empty() ? "" : "__") + file_word(plan.axes[a].key);
  return word;
}

// Draws DIR/map_<column>.png over the keys of `grouping`; returns "" or why it failed (plotting is a
// convenience, never fatal).
std::string plot_map(const SweepPlan& plan, const std::filesystem::path& mean_csv, const std::string& column,
                     const std::filesystem::path& png, const std::vector<std::size_t>& grouping) {
  AtomicFile output(png);
  std::vector<std::string> argv{plot_interpreter(), plot_sweep_script().string(), "--mean", mean_csv.string(),
                                "--column", column, "--output", output.temporary_path().string(), "--title",
                                sweep_map_title(plan, column, grouping)};
  for (std::size_t a : grouping) {
    argv.push_back(plan.axes[a].log ? "--log-key" : "--key");
    argv.push_back(plan.axes[a].key);
  }
  const ProcessOutcome run = run_process(argv, std::chrono::seconds(120));
  if (!run.succeeded()) {
    const std::string why = run.timed_out ? "timed out" : last_output_line(run.output);
    return argv[1] + ": " + (why.empty() ? "failed" : why);
  }
  try {
    output.commit();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

std::string sweep_map_title(const SweepPlan& plan, const std::string& column, const std::vector<std::size_t>& grouping) {
  std::string title = plan.scene.name;
  if (grouping.size() < plan.axes.size()) {
    std::string pooled;
    for (std::size_t a = 0; a < plan.axes.size(); ++a)
      if (std::find(grouping.begin(), grouping.end(), a) == grouping.end()) pooled += (pooled.empty() ? "" : ", ") + plan.axes[a].key;
    title += " (pooled over " + pooled + ")";
  }
  for (const auto& [name, value] : plan.not_aggregated)
    if (name == column) title += "; " + name + " := " + shortest_text(value) + " where aggregation_time is undefined";
  return title;
}

namespace {

// Point p's realization r run through the harness (its own folder under runs/, progress lines prefixed with
// the rank and run); its record, or an exception naming what failed.
SweepRecord run_point(const SweepPlan& plan, const SweepOptions& options, int rank, std::size_t p, std::size_t r) {
  const auto started = std::chrono::steady_clock::now();
  const Scene scene = plan.point_scene(p, r);
  RunOptions run;
  run.out = options.out / "runs" / run_name(p, r);
  run.plot = false;
  run.force = true;  // the sweep's own folder, perhaps left half-written by a killed run
  run.report = nullptr;
  std::optional<PrefixedLines> lines;
  std::optional<std::ostream> prefixed;
  if (options.progress) {
    lines.emplace(*options.progress, "aggkit sweep: [rank " + std::to_string(rank) + "] " + run_name(p, r) + ": ");
    prefixed.emplace(&*lines);
  }
  run.progress = prefixed ? &*prefixed : nullptr;
  run.progress_interval = std::chrono::seconds(60);
  run.warnings = run.progress;
  const RunResult result = run_scene(scene, run);
  for (const auto& record : result.records)
    if (!record.completed()) throw std::runtime_error("engine " + record.label + " failed: " + *record.failure);
  SweepRecord record;
  record.point = p;
  record.realization = r;
  record.values = plan.point(p);
  record.columns = final_columns(scene, result);
  record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  record.rank = rank;
  return record;
}

// The progress line of a finished run: its number among those to do, its point, the mapped columns, seconds.
void print_finished(std::ostream& progress, const SweepPlan& plan, const SweepRecord& record, const std::string& words,
                    std::size_t number, std::size_t todo) {
  std::string shown;
  for (const auto& name : plan.maps)
    for (const auto& [n, v] : record.columns)
      if (n == name) {
        char value[32];
        std::snprintf(value, sizeof value, "%.4g", v);
        shown += ", " + n + " " + value;
      }
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, " (%.1f s)\n", record.seconds);
  progress << "aggkit sweep: [rank " << record.rank << "] " << number << "/" << todo << " " << words << shown << seconds
           << std::flush;
}

// sweep.csv, the means (all keys and each grouping), timing.csv and the maps (rank 0).
void write_sweep_outputs(const SweepPlan& plan, const SweepOptions& options, const std::vector<SweepRecord>& records) {
  write_file_atomically(options.out / "sweep.csv", sweep_csv(plan, records));
  write_file_atomically(options.out / "sweep_mean.csv", sweep_mean_csv(plan, records));
  write_file_atomically(options.out / "timing.csv", sweep_timing_csv(records));
  for (const auto& grouping : plan.groupings)
    write_file_atomically(options.out / ("sweep_mean_by_" + grouping_word(plan, grouping) + ".csv"), sweep_pooled_csv(plan, records, grouping));
  std::vector<std::size_t> every_key;
  for (std::size_t a = 0; a < plan.axes.size(); ++a) every_key.push_back(a);
  if (!options.plot || records.empty()) return;
  for (const std::string& column : plan.maps) {
    std::string why = plot_map(plan, options.out / "sweep_mean.csv", column, options.out / ("map_" + file_word(column) + ".png"), every_key);
    for (const auto& grouping : plan.groupings) {
      if (!why.empty()) break;
      const std::string word = grouping_word(plan, grouping);
      why = plot_map(plan, options.out / ("sweep_mean_by_" + word + ".csv"), column,
                     options.out / ("map_" + file_word(column) + "_by_" + word + ".png"), grouping);
    }
    if (!why.empty() && options.progress) *options.progress << "aggkit sweep: map of " << column << " not drawn: " << why << "\n";
  }
}

}  // namespace

SweepOutcome run_sweep(const SweepPlan& plan, const SweepOptions& options) {
  const MpiWorld world = mpi_world();
  const std::filesystem::path points = options.out / "points";
  prepare_points_folder(options.out, points);
  if (world.rank == 0)
    check_points_fingerprint(points, plan.fingerprint, ".json", "aggkit sweep",
                             "the scene (besides the swept values) or the swept keys changed", options.progress);
  mpi_barrier();

  const std::size_t runs = plan.point_count() * plan.realizations;
  const auto file = [&](std::size_t i) { return points / (run_name(i / plan.realizations, i % plan.realizations) + ".json"); };
  const auto finished = [&](std::size_t i) {
    const std::size_t p = i / plan.realizations, r = i % plan.realizations;
    return parse_record_file(read_text_file(file(i)), p, r, plan.point(p));
  };
  const auto compute = [&](std::size_t i, std::size_t number, std::size_t todo) {
    const std::size_t p = i / plan.realizations, r = i % plan.realizations;
    const std::string words = point_words(plan, p, r);
    try {
      const SweepRecord record = run_point(plan, options, world.rank, p, r);
      write_file_atomically(file(i), record_file_text(record));
      if (options.progress) print_finished(*options.progress, plan, record, words, number, todo);
      return true;
    } catch (const std::exception& e) {
      if (options.progress)
        *options.progress << "aggkit sweep: [rank " << world.rank << "] " << words << " failed: " << e.what() << "\n";
      return false;
    }
  };
  const std::string what = std::to_string(plan.point_count()) + " points x " + std::to_string(plan.realizations) +
                           (plan.realizations == 1 ? " realization" : " realizations");
  const DistributedRuns done = compute_unfinished_runs(runs, [&](std::size_t i) { return finished(i).has_value(); },
                                                       compute, "aggkit sweep", what, options.progress);

  SweepOutcome outcome;
  outcome.runs = runs;
  outcome.reused = done.reused;
  outcome.computed = done.computed;
  outcome.failed = done.failed;
  if (world.rank == 0) {
    std::vector<SweepRecord> records;
    for (std::size_t i = 0; i < runs; ++i)
      if (auto r = finished(i)) records.push_back(std::move(*r));
    outcome.exit_code = outcome.failed > 0 || records.size() < runs ? 1 : 0;
    records = fill_not_aggregated(plan, std::move(records));
    write_sweep_outputs(plan, options, records);
    if (options.progress) {
      *options.progress << "aggkit sweep: " << records.size() << "/" << runs << " runs in " << (options.out / "sweep.csv").string();
      if (outcome.failed) *options.progress << "; " << outcome.failed << " runs failed (run again to retry them)";
      *options.progress << "\n";
    }
  }
  // Every rank returns the same exit status.
  outcome.exit_code = mpi_all(outcome.exit_code == 0) ? 0 : 1;
  return outcome;
}

}  // namespace aggkit
