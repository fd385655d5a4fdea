#pragma once
// Helpers of the DSMC tests: models and ensemble statistics of a moment at output times.
#include <vector>

#include "particle/dsmc/ensemble.hpp"

namespace aggkit::testing {

inline AggregationModel dsmc_model(Kernel kernel, double lambda, std::size_t N = 64) {
  AggregationModel model;
  model.kernel = std::move(kernel);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = N;
  model.initial = monodisperse(N);
  return model;
}

// Per output time and moment order: the values of all runs.
inline std::vector<std::vector<std::vector<double>>> ensemble_moments(const AggregationModel& model,
                                                                       const dsmc::Options& options,
                                                                       const std::vector<double>& times,
                                                                       const std::vector<double>& orders) {
  dsmc::Ensemble ensemble(model, options, times.back());
  std::vector<std::vector<std::vector<double>>> values;
  for (double t : times) {
    std::vector<std::vector<double>> at_t(orders.size());
    for (const auto& snapshot : ensemble.advance_to(t))
      for (std::size_t p = 0; p < orders.size(); ++p) at_t[p].push_back(snapshot.moment(orders[p]));
    values.push_back(std::move(at_t));
  }
  return values;
}

}  // namespace aggkit::testing
