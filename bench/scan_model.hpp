#pragma once
// The shipped scan scene's model (validation/scenes/scan-brownian.toml) for the cycle studies: the Brownian-type
// kernel with exponent a, drop truncation at N = 2^40, unit monodisperse start, on `grid` (the scene's:
// K = 64, r = 1.05), λ = 0.1 as a placeholder.
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

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

// A cached column step of the shipped scan (DIR/points/cycle_column_*_state.txt): the scene's model at (a, λ) and
// the state the step ended in, from the command-line texts of a, λ and the file's path.
struct ColumnStep {
  AggregationModel model;
  std::vector<double> state;
};

inline ColumnStep column_step(const char* a, const char* lambda, const char* state_file) {
  SizeGrid grid;
  grid.resolved = 64;
  grid.ratio = 1.05;
  ColumnStep step{scan_model(grid, std::atof(a)), {}};
  step.model.lambda = ShatteringRate::constant(std::atof(lambda));
  std::ifstream in(state_file);
  for (double v; in >> v;) step.state.push_back(v);
  return step;
}

}  // namespace aggkit::bench
