#include "validation/harness/plot.hpp"

#include <cstdlib>
#include <optional>
#include <variant>
#include <system_error>

#include "validation/io/atomic_file.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

// A numeric statistic the engine reported, if it did.
std::optional<double> statistic(const EngineRecord& record, const std::string& name) {
  for (const auto& s : record.statistics)
    if (s.name == name) {
      if (const double* x = std::get_if<double>(&s.value)) return *x;
      if (const std::int64_t* i = std::get_if<std::int64_t>(&s.value)) return double(*i);
    }
  return std::nullopt;
}

constexpr std::chrono::seconds plot_timeout{120};

std::filesystem::path series_plot_script() {
  return plot_script("AGGKIT_PLOT_SCRIPT", AGGKIT_PLOT_SCRIPT_BUILD, AGGKIT_PLOT_SCRIPT_INSTALL);
}

}  // namespace

std::string to_string(PlotOutcome::Status status) {
  switch (status) {
    case PlotOutcome::Status::written: return "written";
    case PlotOutcome::Status::failed: return "failed";
    case PlotOutcome::Status::skipped: return "skipped";
  }
  return "?";
}

namespace {

// The plotter's arguments after the script, or nullopt if no engine completed.
std::optional<std::vector<std::string>> plot_arguments(const Scene& scene, const std::vector<EngineRecord>& records,
                                                       const OutputFolder& folder, const AtomicFile& png) {
  std::vector<std::string> argv{"--output", png.temporary_path().string(),
                                "--title=" + scene.name};  // one word: a name starting with '-' is no option
  if (scene.compare && !scene.compare->reference.empty()) argv.insert(argv.end(), {"--reference", scene.compare->reference});
  std::size_t plotted = 0;
  for (const auto& record : records) {
    if (!record.completed()) continue;
    argv.insert(argv.end(), {"--series", record.label, folder.series_file(record.label).string()});
    if (!record.distributions.empty())
      argv.insert(argv.end(), {"--distribution", record.label, folder.distribution_file(record.label).string()});
    // An engine with an absolute tolerance atol_k = max(atol k^-q, floor): the plot shows what lies below as
    // unresolved.
    const auto atol = statistic(record, "atol"), exponent = statistic(record, "atol_exponent"),
               floor = statistic(record, "atol_floor");
    if (!record.distributions.empty() && atol && exponent && floor)
      argv.insert(argv.end(), {"--absolute-tolerance", record.label, shortest_text(*atol), shortest_text(*exponent),
                               shortest_text(*floor)});
    ++plotted;
  }
  if (plotted == 0) return std::nullopt;
  return argv;
}

PlotOutcome plot_outcome(const ProcessOutcome& run, AtomicFile& png, const std::string& interpreter,
                         const std::string& script) {
  if (!run.succeeded()) {
    std::string why = !run.started ? run.output
                      : run.timed_out ? "the plotter ran longer than " + std::to_string(plot_timeout.count()) + " s"
                                      : last_output_line(run.output);
    if (why.empty()) why = "the plotter exited with status " + std::to_string(run.exit_status);
    return {PlotOutcome::Status::failed, interpreter + " " + script + ": " + why};
  }
  try {
    png.commit();
  } catch (const std::exception& e) {
    return {PlotOutcome::Status::failed, e.what()};
  }
  return {PlotOutcome::Status::written, ""};
}

}  // namespace

PlotOutcome plot_series(const Scene& scene, const std::vector<EngineRecord>& records, const OutputFolder& folder) {
  AtomicFile png(folder.report_file());
  const auto arguments = plot_arguments(scene, records, folder, png);
  if (!arguments) return {PlotOutcome::Status::skipped, "no engine completed"};
  std::vector<std::string> argv{plot_interpreter(), series_plot_script().string()};
  argv.insert(argv.end(), arguments->begin(), arguments->end());
  return plot_outcome(run_process(argv, plot_timeout), png, argv[0], argv[1]);
}

SeriesPlotter::SeriesPlotter()
    : interpreter_(plot_interpreter()),
      script_(series_plot_script().string()),
      process_(started_plot_command(script_)) {}

PlotOutcome SeriesPlotter::plot(const Scene& scene, const std::vector<EngineRecord>& records, const OutputFolder& folder) {
  AtomicFile png(folder.report_file());
  const auto arguments = plot_arguments(scene, records, folder, png);
  if (!arguments) return {PlotOutcome::Status::skipped, "no engine completed"};  // the destructor ends the process
  return plot_outcome(process_.finish(started_plot_input(*arguments), plot_timeout), png, interpreter_, script_);
}

}  // namespace aggkit
