// [time]: the end time and the output grid.
#include <cmath>

#include "validation/scene/scene_sections.hpp"

namespace aggkit {

namespace {

constexpr double max_outputs = 1e6;  // a grid larger than this is a typo, and would exhaust memory

// Times at which two outputs are considered the same (round-off of k * every).
double time_resolution(double end) { return 1e-9 * end; }

std::vector<double> every_grid(const SceneTable& time, double end) {
  const double every = time.number("every", Bound::positive);
  const double steps = std::floor(end / every + 1e-9);
  if (steps > max_outputs)
    time.fail("every", "at most " + shortest_text(max_outputs) + " outputs up to time.end = " + shortest_text(end));
  std::vector<double> outputs;
  for (double k = 1; k <= steps; ++k) outputs.push_back(k * every);
  return outputs;
}

std::vector<double> listed_grid(const SceneTable& time, double end) {
  std::vector<double> outputs = time.numbers("outputs", Bound::finite);
  if (outputs.size() > max_outputs) time.fail("outputs", "at most " + shortest_text(max_outputs) + " outputs");
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string key = time.key("outputs") + "[" + std::to_string(i) + "]";
    if (!(outputs[i] > 0 && outputs[i] <= end))
      throw InputError(key, shortest_text(outputs[i]), "output times lie in (0, time.end = " + shortest_text(end) + "]");
    if (!(outputs[i] > time_resolution(end)))  // a subnormal first output once stalled CVODE
      throw InputError(key, shortest_text(outputs[i]),
                       "an output time distinguishable from the start: > 1e-9 time.end = " + shortest_text(time_resolution(end)));
    if (i > 0 && !(outputs[i] > outputs[i - 1]))
      throw InputError(key, shortest_text(outputs[i]),
                       "output times must increase; the previous one is " + shortest_text(outputs[i - 1]));
  }
  return outputs;
}

}  // namespace

TimeGrid read_time(const SceneTable& time) {
  time.allow_only({"end", "outputs", "every"});
  TimeGrid grid;
  grid.end = time.number("end", Bound::positive);
  // The integrators take steps of order end·1e-16 and below: a subnormal end (5e-324) stalled CVODE.
  if (!(grid.end >= 1e-200)) time.fail("end", "an end time >= 1e-200 (steps below it underflow)");
  if (time.contains("outputs") && time.contains("every"))
    time.fail("every", "give either time.outputs or time.every, not both");
  if (time.contains("every"))
    grid.outputs = every_grid(time, grid.end);
  else if (time.contains("outputs"))
    grid.outputs = listed_grid(time, grid.end);
  // The end time is always an output; a last output within round-off of it becomes it.
  if (!grid.outputs.empty() && grid.end - grid.outputs.back() <= time_resolution(grid.end)) grid.outputs.pop_back();
  grid.outputs.push_back(grid.end);
  return grid;
}

std::optional<double> matching_output_time(const TimeGrid& grid, double t) {
  for (double output : grid.outputs)
    if (std::abs(output - t) <= time_resolution(grid.end)) return output;
  return std::nullopt;
}

}  // namespace aggkit
