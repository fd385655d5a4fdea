#pragma once
// The shipped scan scene's model (validation/scenes/scan-brownian.toml) for the cycle studies: the Brownian-type
// kernel with exponent a, drop truncation at N = 2^40, unit monodisperse start, on `grid` (the scene's:
// K = 64, r = 1.05), λ = 0.1 as a placeholder.
#include <cstddef>

#include "solvers/model.hpp"

namespace aggkit::bench {

inline AggregationModel scan_model(const SizeGrid& grid, double a) {
  AggregationModel model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(0.1);
  model.size = std::size_t(1) << 40;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid = grid;
  return model;
}

}  // namespace aggkit::bench
