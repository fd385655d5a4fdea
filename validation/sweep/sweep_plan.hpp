#pragma once
// A sweep scene (`aggkit sweep SCENE --out DIR`): any run scene plus a [sweep] section naming scene keys and
// the values each takes; every point of the product of the keys is run `realizations` times. Schema:
//
//   [sweep]
//   "engine.damping" = { from = 10, to = 1e5, count = 7, spacing = "log" }   a range: spacing linear (default)
//                                        or log (from > 0); count values from `from` to `to`
//   "particles.initial.volume_fraction" = [0.05, 0.1]                      or a list of values (numbers,
//                                        strings, booleans), in the order given
//   realizations = 3                     runs per point (default 1): realization r (0-based) runs the point with
//                                        every seed of the scene — particles.seed (its default if absent) and an engine's
//                                        `seed` option — increased by r
//   maps = ["components_fraction"]       the columns drawn (default: the scene's observe.final, else
//                                        observe.series): a heat map over the first two keys, one curve per
//                                        point over one key
//   group_by = ["engine.damping", ["engine.damping", "particles.count"]]
//                                        optional: means pooled over the other swept keys, one table per entry
//                                        (a key or a list of keys, each a swept key once):
//                                        sweep_mean_by_<keys>.csv and map_<column>_by_<keys>.png (sweep.hpp)
//   where_not_aggregated = { fractal_dimension_com = 0.0 }
//                                        optional, off by default: in the runs where aggregation_time is
//                                        undefined (NaN: the run never aggregated; engine dem with gravity)
//                                        these columns take the given value in sweep.csv, the means and the
//                                        maps (whose titles say so) — the paper's map sets F = 0 there
//                                        [Trivino2025, Sec. V]; each column an observe.final observable of the
//                                        scene or one of its values (fractal_dimension_com_at_2tff, ...)
//
// A key is a dotted scene key, quoted (TOML needs the quotes for a dotted name): "particles.count",
// "time.end", "engine.gravity.opening_angle". Engines: `engine.X` is option X of the scene's only engine
// (refused when it has several), `engine[i].X` of engine i (0-based, in scene order), `engine[label].X` of
// the engine with that label. The points vary the first key slowest. Each value is written into the
// scene's TOML and the scene read and its engines built as `aggkit run` would: a key that is not a scene key
// or a value it refuses is an InputError naming the sweep key, the value and the scene's own message.
// `aggkit run` on a sweep scene runs the scene as written (its [sweep] is ignored).
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "validation/scene/scene.hpp"

namespace aggkit {

struct SweepAxis {
  std::string key;                      // as written in [sweep]
  std::vector<nlohmann::json> values;   // numbers, strings or booleans
  bool log = false;                     // a log-spaced range (axes of the plots drawn logarithmic)
};

struct SweepPlan {
  Scene scene;                          // the scene as written: its base point
  std::string source;                   // the scene file, in messages
  std::string text;                     // the scene's TOML without [sweep]
  std::filesystem::path folder;         // relative paths in the scene are taken from here
  std::vector<SweepAxis> axes;
  std::size_t realizations = 1;
  std::vector<std::string> maps;        // columns to draw
  std::vector<std::vector<std::size_t>> groupings;  // group_by: indices into `axes`, in the order written
  std::vector<std::pair<std::string, double>> not_aggregated;  // where_not_aggregated: column, value
  // Everything a run's result depends on besides its swept values and realization: finished runs are reused
  // by a later sweep only if this is unchanged.
  std::string fingerprint;

  std::size_t point_count() const;
  // The values of point p (first key slowest), one per axis.
  std::vector<nlohmann::json> point(std::size_t p) const;
  // The scene of point p, realization r (its TOML text, and read).
  std::string point_text(std::size_t p, std::size_t r) const;
  Scene point_scene(std::size_t p, std::size_t r) const;
};

// Reads and validates a sweep scene: the base scene, every value of every key applied alone, and every point
// of the product (up to 1000 points), each read and its engines built. InputError names the key.
SweepPlan load_sweep_plan(const std::filesystem::path& path);
SweepPlan parse_sweep_plan(std::string_view text, const std::string& source = "scene",
                           const std::filesystem::path& folder = {});

// A value as a CSV cell or a message shows it: numbers shortest, strings bare.
std::string sweep_value_text(const nlohmann::json& value);

}  // namespace aggkit
