#pragma once
// The per-engine output files: <engine>/series.csv (header `t,<observables as written in the scene>`, then
// `<observable>_stderr` for each observable when the engine ran an ensemble of more than one realisation; one
// row per output time) and <engine>/distribution.csv (`t,k,n,cdf`: n_k at each requested time and the
// fraction of clusters of size <= k, Σ_{j<=k} n_j / Σ_j n_j; on a graded grid one row per pivot, n the
// density its number stands for under the scene's `grid`); full precision.
#include <filesystem>

#include "solvers/size_grid.hpp"
#include "validation/harness/engine_record.hpp"

namespace aggkit {

void write_series_csv(const std::filesystem::path& file, const Observation& observe, const EngineRecord& record);
void write_distribution_csv(const std::filesystem::path& file, const EngineRecord& record, const SizeGrid& grid);

}  // namespace aggkit
