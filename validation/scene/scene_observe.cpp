// [observe] and [compare]: what is recorded and how engines are compared.
#include <algorithm>
#include <cmath>

#include "validation/scene/scene_sections.hpp"

namespace aggkit {

bool Observation::has_series_measures() const {
  for (const auto& name : final_state)
    if (Observable::from_name(name)->is_series_measure()) return true;
  return false;
}

namespace {

// observe.final: observables of the final configuration (only with [particles]) and measures of a series
// of observe.series (any scene), each once.
std::vector<std::string> read_final_state(const SceneTable& observe, const Scene& scene, const Observation& observation) {
  const std::vector<std::string> names = observe.strings("final");
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string key = observe.key("final") + "[" + std::to_string(i) + "]";
    const auto observable = Observable::from_name(names[i]);
    if (!observable) throw InputError(key, "\"" + names[i] + "\"", Observable::forms());
    if (std::find(names.begin(), names.begin() + i, names[i]) != names.begin() + i)
      throw InputError(key, "\"" + names[i] + "\"", "each observable once");
    if (observable->is_series_measure()) {
      const std::string source = observable->source();
      bool observed = false;
      for (const auto& o : observation.series) observed = observed || o.name() == source;
      if (!observed)
        throw InputError(key, "\"" + names[i] + "\"", "a measure of a series of observe.series (\"" + source + "\" is not one)");
    } else if (!scene.particles) {
      throw InputError(key, "\"" + names[i] + "\"",
                       "a measure of a series (oscillation_period:<series>, ...): observables of the final "
                       "configuration need a [particles] section");
    }
  }
  return names;
}

// observe.window: [start, end] inside the run, with at least 16 uniformly spaced output times (the series
// measures need them); default the last half of the run.
void read_window(const SceneTable& observe, const Scene& scene, Observation& observation) {
  const double end = scene.time.end;
  observation.window_start = 0.5 * end;
  observation.window_end = end;
  if (observe.contains("window")) {
    const std::vector<double> w = observe.numbers("window", Bound::finite);
    std::string text = "[";  // the value as written, for the message; built by appends (GCC 12 -Wrestrict)
    for (std::size_t i = 0; i < w.size(); ++i) {
      if (i > 0) text += ", ";
      text += shortest_text(w[i]);
    }
    text += ']';
    if (w.size() != 2 || !(w[0] >= 0 && w[0] < w[1] && w[1] <= end * (1 + 1e-12)))
      throw InputError(observe.key("window"), text, "[start, end] with 0 <= start < end <= time.end = " + shortest_text(end));
    observation.window_start = w[0];
    observation.window_end = w[1];
  }
  if (!observation.has_series_measures()) return;
  std::vector<double> times;
  for (double t : scene.time.outputs)
    if (t >= observation.window_start - 1e-9 * end && t <= observation.window_end + 1e-9 * end) times.push_back(t);
  const std::string what = "a window [" + shortest_text(observation.window_start) + ", " +
                           shortest_text(observation.window_end) + "]";
  const std::string key = observe.contains("window") ? observe.key("window") : observe.key("final");
  if (times.size() < 16)
    throw InputError(key, what + " with " + std::to_string(times.size()) + " output times",
                     "at least 16 output times for the series measures of observe.final (time.every)");
  const double dt = (times.back() - times.front()) / double(times.size() - 1);
  for (std::size_t i = 1; i < times.size(); ++i)
    if (std::abs(times[i] - times[i - 1] - dt) > 1e-6 * dt)
      throw InputError(key, what, "uniformly spaced output times in the window for the series measures of "
                                  "observe.final (time.every)");
}

// The tolerance `name` of `table`: a number r, or { relative = r, stderr = k }; with `stated_value`, also
// { value = v, relative = r, stderr = k } (a final value against a stated constant).
Tolerance read_tolerance(const SceneTable& table, const std::string& name, bool stated_value = false) {
  const toml::node* value = table.find(name);
  if (value && value->is_table()) {
    const SceneTable form = table.table(name);
    if (stated_value) form.allow_only({"relative", "stderr", "value"});
    else form.allow_only({"relative", "stderr"});
    if (!form.contains("relative") && !form.contains("stderr"))
      throw InputError(table.key(name), scene_text(*value),
                       stated_value ? "a number, { relative = r, stderr = k } or { value = v, relative = r }"
                                    : "a number or { relative = r, stderr = k }");
    Tolerance tolerance{name, form.optional_number("relative", Bound::non_negative).value_or(0.0),
                        form.optional_number("stderr", Bound::non_negative)};
    if (stated_value) tolerance.value = form.optional_number("value", Bound::finite);
    return tolerance;
  }
  return {name, table.number(name, Bound::non_negative), std::nullopt};
}

bool has_stated_value(const SceneTable& table, const std::string& name) {
  const toml::node* value = table.find(name);
  return value && value->is_table() && table.table(name).contains("value");
}

// A table of tolerances { name = r } or { name = { relative = r, stderr = k } } for the names in `allowed`;
// with `stated_values`, an entry { value = v, ... } may name any final value (checked when the engines ran).
std::vector<Tolerance> read_tolerances(const SceneTable& table, const std::vector<std::string>& allowed,
                                       const std::string& where, bool stated_values = false) {
  std::vector<Tolerance> tolerances;
  for (auto&& [key, value] : table.raw()) {
    const std::string name(key.str());
    const bool stated = stated_values && has_stated_value(table, name);
    if (!stated && std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw InputError(table.key(name), scene_text(value),
                       "tolerances are given for observables in " + where + ": " + (allowed.empty() ? "none" : join(allowed)) +
                           (stated_values ? "; or { value = v, relative = r } for any final value" : ""));
    tolerances.push_back(read_tolerance(table, name, stated_values));
  }
  return tolerances;
}

// Bytes of a trajectory frame per particle (validation/io/particle_snapshot.hpp): position, velocity and
// angular velocity (3 Float64 each), radius (Float64), the vertex cell's connectivity and offset (Int64 each),
// cluster (Int32) and cell type (UInt8), in base64 (4/3); the frame's XML (under 2 kB) aside. 60 particles
// measured 156 B a particle with the XML (tests/apps/check_trajectory.py checks the files against this).
constexpr double frame_bytes_per_particle = (12 * 8 + 4 + 1) * 4.0 / 3.0;

// observe.snapshots: true, false, or { every = Δt, max_frames = n, max_megabytes = m } (a trajectory).
void read_snapshots(const SceneTable& observe, const Scene& scene, Observation& observation) {
  const toml::node* value = observe.find("snapshots");
  if (!value) return;
  if (value->is_boolean()) {
    observation.snapshots = value->as_boolean()->get();
  } else if (!value->is_table()) {
    observe.fail("snapshots", "true, false or { every = Δt } (a trajectory)");
  } else {
    const SceneTable form = observe.table("snapshots");
    form.allow_only({"every", "max_frames", "max_megabytes"});
    observation.snapshots = true;
    observation.frame_every = form.number("every", Bound::positive);
    const std::size_t max_frames = form.optional_count("max_frames", 1).value_or(1000);
    const double max_megabytes = form.optional_number("max_megabytes", Bound::positive).value_or(2048);
    // Frames at the output times, each at least `every` after the one before (within round-off).
    double last = 0;
    const std::vector<double>& outputs = scene.time.outputs;
    for (std::size_t k = 0; k < outputs.size(); ++k)
      if (outputs[k] - last >= observation.frame_every * (1 - 1e-9)) {
        observation.frame_outputs.push_back(k);
        last = outputs[k];
      }
    const std::size_t frames = observation.frame_outputs.size() + 1;  // and t = 0
    if (frames > max_frames)
      form.fail("every", "a spacing giving at most max_frames = " + std::to_string(max_frames) + " frames (this one gives " +
                             std::to_string(frames) + " at the output times); raise every or max_frames");
    if (scene.particles) {
      const double megabytes = double(frames) * double(scene.particles->count) * frame_bytes_per_particle / 1e6;
      if (megabytes > max_megabytes)
        form.fail("every", "a trajectory within max_megabytes = " + shortest_text(max_megabytes) + " (this one: " +
                               std::to_string(frames) + " frames of " + std::to_string(scene.particles->count) +
                               " particles, about " + shortest_text(std::round(megabytes)) + " MB); raise every or max_megabytes");
    }
  }
  if (observation.snapshots && !scene.particles) observe.fail("snapshots", "false: snapshots need a [particles] section");
}

}  // namespace

Observation read_observation(const SceneTable& observe, const Scene& scene) {
  observe.allow_only({"series", "distributions", "final", "snapshots", "window", "times_ff"});
  Observation observation;
  const std::vector<std::string> names = observe.strings("series");
  if (names.empty()) observe.fail("series", "at least one observable: " + std::string(Observable::forms()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string key = observe.key("series") + "[" + std::to_string(i) + "]";
    const auto observable = Observable::from_name(names[i]);
    if (!observable) throw InputError(key, "\"" + names[i] + "\"", Observable::forms());
    if (observable->is_profile())
      throw InputError(key, "\"" + names[i] + "\"", "a number per output time; a profile belongs in observe.final");
    const std::size_t largest = scene.has_model ? scene.model.size : scene.particles ? scene.particles->count : 0;
    if (observable->type().size_parameter && observable->parameter() > double(largest))
      throw InputError(key, "\"" + names[i] + "\"",
                       "n<k> with k <= " + std::string(scene.has_model ? "model.size" : "particles.count") + " = " +
                           std::to_string(largest));
    for (const auto& earlier : observation.series)
      if (earlier.name() == names[i]) throw InputError(key, "\"" + names[i] + "\"", "each observable once");
    observation.series.push_back(*observable);
  }
  if (observe.contains("distributions")) {
    const std::vector<double> times = observe.numbers("distributions", Bound::finite);
    for (std::size_t i = 0; i < times.size(); ++i) {
      const std::string key = observe.key("distributions") + "[" + std::to_string(i) + "]";
      const auto t = matching_output_time(scene.time, times[i]);
      if (!t) throw InputError(key, shortest_text(times[i]), "one of the output times (see [time])");
      if (std::find(observation.distribution_times.begin(), observation.distribution_times.end(), *t) !=
          observation.distribution_times.end())
        throw InputError(key, shortest_text(times[i]), "each time once");
      observation.distribution_times.push_back(*t);
    }
    std::sort(observation.distribution_times.begin(), observation.distribution_times.end());
  }
  if (observe.contains("final")) observation.final_state = read_final_state(observe, scene, observation);
  read_window(observe, scene, observation);
  read_snapshots(observe, scene, observation);
  if (observe.contains("times_ff")) {
    // Multiples k of the free-fall time, increasing, each > 0 and at most 10^6.
    const std::vector<double> k = observe.numbers("times_ff", Bound::finite);
    if (!scene.particles) observe.fail("times_ff", "no times_ff without [particles] (free-fall times of particle engines)");
    if (k.empty()) observe.fail("times_ff", "at least one multiple of t_ff, e.g. [1.0, 2.0]");
    for (std::size_t i = 0; i < k.size(); ++i)
      if (!(k[i] > 0 && k[i] <= 1e6) || (i > 0 && !(k[i] > k[i - 1])))
        throw InputError(observe.key("times_ff") + "[" + std::to_string(i) + "]", shortest_text(k[i]),
                         "increasing multiples of the free-fall time, each in (0, 1e6]");
    observation.times_ff = k;
  }
  return observation;
}

ComparisonPlan read_comparison(const SceneTable& compare, const Scene& scene) {
  compare.allow_only({"reference", "tolerance", "final", "distribution"});
  ComparisonPlan plan;
  // Without a reference only final values against stated values: every entry of `final` has a `value`.
  bool only_stated_values = !compare.contains("reference") && !compare.contains("tolerance") &&
                            !compare.contains("distribution") && compare.contains("final");
  if (only_stated_values) {
    const SceneTable final = compare.table("final");
    for (auto&& [key, value] : final.raw()) only_stated_values = only_stated_values && has_stated_value(final, std::string(key.str()));
  }
  std::vector<std::string> labels;
  for (const auto& engine : scene.engines) labels.push_back(engine.label);
  if (!only_stated_values) {
    plan.reference = compare.string("reference");
    if (!scene.find_engine(plan.reference)) compare.fail("reference", "the label of an engine of this scene: " + join(labels));
    if (scene.engines.size() < 2)
      compare.fail("reference", "a comparison needs a second engine besides the reference; this scene has only " +
                                    join(labels) + " (or compare final values with stated ones: final = { x = { value = v, relative = r } })");
  }
  if (const auto tolerance = compare.optional_table("tolerance")) {
    std::vector<std::string> series;
    for (const auto& o : scene.observe.series) series.push_back(o.name());
    plan.tolerances = read_tolerances(*tolerance, series, "observe.series");
  }
  if (compare.contains("distribution")) {
    if (scene.observe.distribution_times.empty())
      compare.fail("distribution", "a tolerance for the size distributions of observe.distributions (none are observed)");
    plan.distribution = read_tolerance(compare, "distribution");
  }
  if (const auto final = compare.optional_table("final")) {
    std::vector<std::string> scalars;  // profiles have no single number to compare
    for (const auto& name : scene.observe.final_state)
      if (!Observable::from_name(name)->is_profile()) scalars.push_back(name);
    plan.final_tolerances = read_tolerances(*final, scalars, "observe.final (numbers, not profiles)", true);
  }
  return plan;
}

}  // namespace aggkit
