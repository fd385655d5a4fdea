#pragma once
// The plot of a run, DIR/report.png, drawn by validation/harness/plot_series.py with matplotlib: one panel per
// observable with every engine overlaid, plus the size distributions if any were requested. Plotting is a
// convenience: a failure is reported, never fatal.
#include <string>
#include <vector>

#include "validation/harness/engine_record.hpp"
#include "validation/harness/output_folder.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"  // plot_interpreter(), shared by every plotter

namespace aggkit {

struct PlotOutcome {
  enum class Status { written, failed, skipped };
  Status status = Status::skipped;
  std::string message;  // why it failed (the plotter's last words) or was skipped
};
std::string to_string(PlotOutcome::Status status);

// Plots the series (and distributions) already written to `folder` for the engines that completed.
// The interpreter is validation/io/python_plotter.hpp's; the script is $AGGKIT_PLOT_SCRIPT, else the one in the source or install tree.
PlotOutcome plot_series(const Scene& scene, const std::vector<EngineRecord>& records, const OutputFolder& folder);

// The same plot with the interpreter started at construction (before the engines run), so that its
// matplotlib import overlaps them; `plot` draws exactly what plot_series draws, once. Destroyed without
// `plot` (an error, no plot wanted after all), the interpreter is killed and reaped.
class SeriesPlotter {
 public:
  SeriesPlotter();
  PlotOutcome plot(const Scene& scene, const std::vector<EngineRecord>& records, const OutputFolder& folder);

 private:
  std::string interpreter_, script_;
  StartedProcess process_;
};

}  // namespace aggkit
