#pragma once
// A range of values in a scene, { from = .., to = .., count = .. (, spacing = "log") }, shared by the scan
// ([scan] a, lambda) and the sweep ([sweep] keys). Internal to the scene readers; needs toml++.
#include <vector>

#include "validation/scene/scene_table.hpp"

namespace aggkit {

// `count` values from `from` to `to` (both included), linear (default) or log spacing (from > 0); values
// rounded to 12 significant digits (0.55 + 0.05 k reads 0.6, in CSVs and file names) and the last exactly
// `to`. InputError naming the key for unknown keys, count 0 or > `max_count`, to <= from, log with from <= 0.
std::vector<double> read_value_range(const SceneTable& range, std::size_t max_count, bool& log_spacing);

}  // namespace aggkit
