#pragma once
// `aggkit sweep SCENE --out DIR`: every point of a sweep scene's product of keys (sweep_plan.hpp), each run
// `realizations` times, the runs spread over the MPI ranks (`mpirun -np K aggkit sweep ...`; each rank draws
// the next run when it is free) and kept in DIR/points/ as they finish, so that an interrupted sweep resumes
// without rerunning them (validation/runs/run_store.hpp, shared with `aggkit scan`). Outputs (rank 0, each
// written atomically):
//   DIR/sweep.csv        one row per point and realization: the swept values (a column per key, as written),
//                        realization, then the run's final values — every entry of each engine's final.json
//                        (particle engines: observe.final and the engine's own values, except its wall_seconds,
//                        which is timing.csv's), and the observe.series
//                        values at the last output time not among them; with several engines each column is
//                        prefixed "<label>." — NaN where a value is undefined (e.g. T_agg of a run that never
//                        aggregated)
//   DIR/sweep_mean.csv   one row per point: the swept values, runs (the finished realizations), and for each
//                        column <name> (mean over the runs where it is finite), <name>_stderr (sample standard
//                        deviation / √n; 0 for n = 1) and <name>_n (the n)
//   DIR/timing.csv       point, realization, seconds, rank of each run (kept out of sweep.csv)
//   DIR/map_<column>.png for each of [sweep] maps: a heat map of the mean over the first two keys (one panel per
//                        value of further keys), or the mean ± standard error against the key for one key;
//                        the title says which columns where_not_aggregated set
//   DIR/sweep_mean_by_<keys>.csv   for each [sweep] group_by entry (keys joined by "__"): the means pooled over
//                        the other keys and the realizations, a row per value of the grouped keys
//   DIR/map_<column>_by_<keys>.png its maps, as above over the grouped keys (title: what was pooled over)
//   DIR/runs/point<i>_r<r>/   each run's own outputs, as `aggkit run` writes them (series.csv, final.json, ...)
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "validation/sweep/sweep_plan.hpp"

namespace aggkit {

struct SweepOptions {
  std::filesystem::path out;
  bool plot = true;
  std::ostream* progress = nullptr;  // progress lines (each rank its own runs); nullptr: quiet
};

struct SweepOutcome {
  std::size_t runs = 0;      // points × realizations
  std::size_t reused = 0;    // finished earlier
  std::size_t computed = 0;  // by this rank
  std::size_t failed = 0;    // all ranks; a rerun retries them
  int exit_code = 0;         // 0 complete, 1 some runs failed
};

// Throws InputError for an unusable output folder (key "--out").
SweepOutcome run_sweep(const SweepPlan& plan, const SweepOptions& options);

// The title of the map of `column` over the keys `grouping` (indices into plan.axes): the scene's name, the
// keys pooled over, and the value where_not_aggregated gives the column.
std::string sweep_map_title(const SweepPlan& plan, const std::string& column, const std::vector<std::size_t>& grouping);

}  // namespace aggkit
