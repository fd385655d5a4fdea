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

PlotOutcome plot_series(const Scene& scene, const std::vector<EngineRecord>& records, const OutputFolder& folder) {
  AtomicFile png(folder.report_file());
  std::vector<std::string> argv{plot_interpreter(), series_plot_script().string(), "--output", png.temporary_path().string(),
                                "--title=" + scene.name};  // one word: a name starting with '-' is no option
  if (scene.compare) argv.insert(argv.end(), {"--reference", scene.compare->reference});
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
  if (plotted == 0) return {PlotOutcome::Status::skipped, "no engine completed"};

  const ProcessOutcome run = run_process(argv, plot_timeout);
  if (!run.succeeded()) {
    std::string why = !run.started ? run.output
                      : run.timed_out ? "the plotter ran longer than " + std::to_string(plot_timeout.count()) + " s"
                                      : last_output_line(run.output);
    if (why.empty()) why = "the plotter exited with status " + std::to_string(run.exit_status);
    return {PlotOutcome::Status::failed, argv[0] + " " + argv[1] + ": " + why};
  }
  try {
    png.commit();
  } catch (const std::exception& e) {
    return {PlotOutcome::Status::failed, e.what()};
  }
  return {PlotOutcome::Status::written, ""};
}

}  // namespace aggkit
