#pragma once
// A scene: one validation run described in a TOML file. The schema, every key:
//
//   name = "..."                                   (required)
//   tier = "fast"                                  fast | full (default fast): `aggkit validate --tier fast`
//                                                  runs the fast scenes, `--tier full` every scene
//   [model]                                        required by the kinetic engines (cvode, exact, ...)
//   kernel = { name = "ballistic" }                a kernel of the registry and its parameters
//                                                  (solvers/kernels.hpp; `aggkit kernels` lists them)
//   lambda = 0.01                                  or { initial = .., slope = .. } (λ = initial + slope t)
//                                                  or { times = [..], values = [..] } (piecewise linear);
//                                                  default 0
//   size = 5000                                    truncation N >= 2 (required)
//   truncation = "drop"                            drop | cutoff (default drop)
//   grid = { resolved = 64, ratio = 1.05 }         optional graded size grid (its rows: solvers/size_grid.hpp;
//                                                  scheme = "four-moment" by default); absent: uniform
//   initial = { kind = "monodisperse" }            optional density (default 1);
//                                                  or { kind = "table", n = [n_1, n_2, ...] }
//   [particles]                                    required by the particle engines (ed, ...); see
//                                                  scene_particles.cpp for the keys
//   [time]
//   end = 100.0                                    (required, > 0)
//   outputs = [1.0, 10.0]  or  every = 1.0         increasing, in (0, end]; end is always an output
//   [[engine]]                                     one table per engine, run in this order
//   name = "cvode"                                 the kinds and their options: `aggkit run --help`
//   label = "cvode-direct"                         optional, default the name; unique; output folder
//   ...                                            the engine's own options (its option table,
//                                                  validation/engines/engine_<name>.cpp), checked when
//                                                  the engines are built (validation/engines/engine.hpp)
//   [observe]
//   series = ["M0", "M2", "mass_leak", "n1"]       (required; the forms: validation/observables/)
//   distributions = [1.0, 100.0]                   optional; each one of the output times
//   final = ["contacts", "fractal_dimension_box"]  particle engines: observables of the final configuration,
//                                                  written to <engine>/final.json (profiles such as
//                                                  pair_distribution to <engine>/<name>.csv);
//                                                  any engine: measures of a series of observe.series,
//                                                  "oscillation_period:M0", taken on each realization's
//                                                  series over observe.window (mean and standard error over
//                                                  the realizations; summary.json engines.<label>.final)
//   window = [1500.0, 3000.0]                      the time window of the series measures: output times in
//                                                  it uniformly spaced, at least 16 (default: the last half
//                                                  of the run, [end/2, end])
//   snapshots = true                               particle engines: the final configuration as
//                                                  <engine>/final.vtu and <engine>/final.png (default false)
//   snapshots = { every = 0.5 }                    the same, and a trajectory of the first realization:
//                                                  <engine>/trajectory/frame_NNNNN.vtu at t = 0 and at the
//                                                  output times at least `every` after the previous frame,
//                                                  and <engine>/trajectory.pvd (ParaView's time series);
//                                                  at most max_frames (default 1000) files and an estimated
//                                                  max_megabytes (default 2048) of disk, checked before the run
//   times_ff = [1.0, 1.5, 2.0, 3.0]                particle engines with a free-fall time t_ff (dem with
//                                                  gravity [Trivino2025, eq. 9]): the observe.final values
//                                                  and the engine's own state values (K/|P|) also at
//                                                  t = k t_ff of each realization, in final.json as
//                                                  <name>_at_<k>tff (validation/engines/particle_runner.hpp);
//                                                  increasing, each > 0 (default none)
//   [sweep]                                        optional: the parameter sweep of `aggkit sweep`
//                                                  (validation/sweep/sweep_plan.hpp); `aggkit run` ignores
//                                                  it and runs the scene as written (its base point)
//   [compare]                                      optional
//   reference = "exact"                            an engine label (required unless every entry is a
//                                                  final value with a stated `value`, below)
//   tolerance = { M0 = 1e-6, M2 = 1e-6 }           max relative error over the output times, per series
//                                                  observable; observables without one are reported only;
//                                                  or { M0 = { relative = 0.01, stderr = 3 } }: at each time
//                                                  |x - x_ref| <= relative |x_ref| + stderr σ, σ the combined
//                                                  standard error of ensemble engines (dsmc with runs > 1,
//                                                  particle engines with realizations > 1)
//   final = { contacts = { relative = 0.05, stderr = 3 } }  the same forms for values of observe.final (the
//                                                  means over the realizations; σ their standard errors),
//                                                  e.g. TS against ED, which agree in distribution, or the
//                                                  oscillation period of DSMC against CVODE
//   final = { contacts_with_self = { value = 0.5, relative = 0.05 } }  a final value against a stated constant
//                                                  (a published figure, an exact value): each engine's mean
//                                                  x passes when |x - value| <= relative |value| + stderr σ,
//                                                  σ its standard error. Such an entry may name any number of
//                                                  the engines' final.json (aggregation_time_ff of dem, ...),
//                                                  not only observe.final; an engine without it fails. A
//                                                  [compare] whose entries all have a value needs no
//                                                  reference (nor a second engine)
//   distribution = { relative = 0.01, stderr = 3 }  the size distributions at observe.distributions: at each
//                                                  such time E = ||n - n_ref||_2 over the sizes, allowed
//                                                  relative ||n_ref||_2 + stderr sqrt(Σ_k σ_k²), σ_k the
//                                                  standard error of the engine's mean n_k over its
//                                                  realizations; the note gives E per time and the mean
//                                                  single-realization error ([Kalinov2022, Table 1])
//
// Unknown keys anywhere are errors.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "particle/common/particle_system.hpp"
#include "solvers/model.hpp"
#include "validation/observables/observable.hpp"

namespace aggkit {

// How n_k(0) was given; the exact engine needs a unit monodisperse start.
struct InitialCondition {
  enum class Kind { monodisperse, table };
  Kind kind = Kind::monodisperse;
  double density = 1.0;  // of the monomers, for Kind::monodisperse
};

struct TimeGrid {
  double end = 0.0;
  std::vector<double> outputs;  // increasing, in (0, end], the last one is `end`
};

struct Observation {
  std::vector<Observable> series;
  std::vector<double> distribution_times;  // each one of TimeGrid::outputs
  std::vector<std::string> final_state;    // names of final-configuration observables (particle engines)
                                           // and series measures (any engine, e.g. oscillation_period:M0)
  bool snapshots = false;                  // final configuration as .vtu and .png (particle engines)
  double frame_every = 0;                  // snapshots = { every }: the trajectory's spacing (0: no trajectory)
  std::vector<std::size_t> frame_outputs;  // the indices of the output times with a trajectory frame (besides t = 0)
  double window_start = 0, window_end = 0;  // observe.window: where the series measures are taken
  std::vector<double> times_ff;            // observe.times_ff: multiples of the free-fall time (particle engines)
  bool has_series_measures() const;
};

struct Tolerance {
  std::string observable;  // a name in Observation::series (or a final value)
  double relative_error;   // the largest allowed max-over-time relative error (0 if only `stderr` is given)
  // With `stderr = k`: at each output time |x - x_ref| may also use k combined standard errors
  // sqrt(σ² + σ_ref²) of the two engines' ensembles (allowed: relative_error |x_ref| + k σ).
  std::optional<double> standard_errors = std::nullopt;
  // compare.final only: a stated constant (a published figure) that each engine's final value is checked
  // against, instead of the reference engine's.
  std::optional<double> value = std::nullopt;
};

struct ComparisonPlan {
  std::string reference;  // an engine label; empty when every entry is a final value against a stated value
  std::vector<Tolerance> tolerances;        // series observables
  std::vector<Tolerance> final_tolerances;  // observe.final values
  std::optional<Tolerance> distribution = std::nullopt;  // compare.distribution: the size distributions (observable "distribution")
  const Tolerance* tolerance_for(std::string_view observable) const;  // nullptr: reported only
  const Tolerance* final_tolerance_for(std::string_view observable) const;
};

// One [[engine]] table as written: the engine is built from it (and its options checked against the kind's
// option table) by validation/engines/engine.hpp, which the scene does not depend on.
struct EngineSpec {
  std::string name;         // the kind
  std::string label;        // unique in the scene: output folder, comparison key
  std::string key;          // the table's dotted key in messages: "engine[1]"
  nlohmann::json options;   // every other key of the table (an object)
};

// Which `aggkit validate` tier runs the scene: fast scenes run in every validation (and in CI), full ones
// only under `--tier full`.
enum class SceneTier { fast, full };
const char* to_string(SceneTier tier);

struct Scene {
  std::string name;
  SceneTier tier = SceneTier::fast;
  std::filesystem::path path;  // the file it was read from; empty for a scene parsed from text
  AggregationModel model;     // meaningful only if has_model
  bool has_model = false;     // the scene has a [model] section
  InitialCondition initial;
  std::optional<ParticleSystem> particles;  // the [particles] section, if any
  TimeGrid time;
  std::vector<EngineSpec> engines;  // in run order
  Observation observe;
  std::optional<ComparisonPlan> compare;
  // Not a scene key: the PETSc options of `aggkit run SCENE --out DIR -- OPTIONS`, which each snes engine
  // of this scene's run hands its own solve after its petsc_options (solvers/petsc_options.hpp).
  std::string command_line_petsc_options;

  const EngineSpec* find_engine(std::string_view label) const;  // nullptr if absent
};

// Reads and validates a scene file; throws InputError for a missing or unreadable file, malformed TOML and
// every bad key or value (the message names the dotted key, the value and what is allowed).
Scene load_scene(const std::filesystem::path& path);
// The same for TOML text; `source` names it in messages.
Scene parse_scene(std::string_view text, const std::string& source = "scene");
// The same, with relative paths in the scene (a [particles] start file) taken from `folder`.
Scene parse_scene(std::string_view text, const std::string& source, const std::filesystem::path& folder);

}  // namespace aggkit
