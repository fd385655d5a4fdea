#pragma once
// What the periodic-orbit tests share (tests/solvers/test_limit_cycle.cpp, test_hopf_normal_form.cpp): their
// model and an independent period.
//
// The period of M0 in a long CVODE run, independently of the shooting code (tests/solvers/test_limit_cycle.cpp,
// test_hopf_normal_form.cpp): the mean spacing of the upward crossings of M0 through its mean over `cycles`
// periods after `settle`, each crossing linearly interpolated between outputs 1/400 of a period apart
// (interpolation error ~1e-6 of a period per crossing). The run starts from the model's initial state, or
// from `start` where given.
#include <catch2/catch.hpp>

#include <span>
#include <vector>

#include "solvers/cvode_integrator.hpp"

namespace aggkit::testing {

// Brownian kernel on the graded grid K = 32, r = 1.1 up to N = 2^20 (about 140 classes): the tail
// e^{-0.65 λ k} is resolved for λ ≥ 1e-3 (λN ≥ 8).
inline AggregationModel graded_brownian(double a, double lambda) {
  AggregationModel model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = std::size_t(1) << 20;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid.resolved = 32;
  model.grid.ratio = 1.1;
  return model;
}

// Ballistic kernel with shattering λ and drop truncation at N, monodisperse start: a run that leaks mass fast at
// small N (77 % by t = 20 at N = 64, λ = 0.01).
inline AggregationModel leaking_ballistic(std::size_t N, double lambda) {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(lambda);
  model.size = N;
  model.truncation = Truncation::drop;
  model.initial = monodisperse(N);
  return model;
}

inline double time_series_period(const AggregationModel& model, double period, double settle, int cycles,
                                 std::span<const double> start = {}) {
  const double spacing = period / 400.0, end = settle + cycles * period;
  std::vector<double> times, m0;
  for (double t = settle; t <= end; t += spacing) times.push_back(t);
  IntegratorOptions options;
  options.rtol = 1e-10;
  IntegratorRestart from;
  from.densities.assign(start.begin(), start.end());
  integrate(model, times, options, [&](double, std::span<const double> n, double) {
    double sum = 0.0;
    for (double v : n) sum += v;
    m0.push_back(sum);
  }, start.empty() ? nullptr : &from);
  double mean = 0.0;
  for (double v : m0) mean += v;
  mean /= double(m0.size());
  std::vector<double> up;
  for (std::size_t i = 1; i < m0.size(); ++i)
    if (m0[i - 1] < mean && m0[i] >= mean) up.push_back(times[i - 1] + spacing * (mean - m0[i - 1]) / (m0[i] - m0[i - 1]));
  REQUIRE(up.size() >= 3);
  return (up.back() - up.front()) / double(up.size() - 1);
}

}  // namespace aggkit::testing
