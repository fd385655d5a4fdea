// Straight-line least squares (GSL gsl_fit_linear) and its standard errors, on cases whose answer is
// known in closed form or by the sampling distribution of the slope.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "analysis/input_error.hpp"
#include "analysis/least_squares.hpp"

using namespace aggkit;

TEST_CASE("least squares: slope, intercept and standard errors of a hand-computed case", "[fit]") {
  // y = 1 + 2x + e with residuals e = (1, -2, 0, 2, -1), orthogonal to 1 and to x, so the fit returns
  // c0 = 1, c1 = 2 exactly. With n = 5, x̄ = 2, Σ(x-x̄)² = 10, Σe² = 10: s² = 10/3,
  // se(c1) = sqrt(s²/10) = sqrt(1/3), se(c0) = sqrt(s² (1/5 + 4/10)) = sqrt(2).
  const std::vector<double> x{0, 1, 2, 3, 4};
  const std::vector<double> e{1, -2, 0, 2, -1};
  std::vector<double> y;
  for (std::size_t i = 0; i < x.size(); ++i) y.push_back(1.0 + 2.0 * x[i] + e[i]);
  const LineFit fit = fit_line(x, y);
  REQUIRE(fit.valid());
  CHECK(fit.points == 5);
  CHECK(fit.slope == Approx(2.0).epsilon(1e-14));
  CHECK(fit.intercept == Approx(1.0).epsilon(1e-14));
  CHECK(fit.residual_sum_of_squares == Approx(10.0).epsilon(1e-14));
  CHECK(fit.slope_error == Approx(std::sqrt(1.0 / 3.0)).epsilon(1e-14));
  CHECK(fit.intercept_error == Approx(std::sqrt(2.0)).epsilon(1e-14));
}

TEST_CASE("least squares: the standard error matches the scatter of slopes over noisy replicas", "[fit]") {
  // y = 0.5 - 0.3 x + σ ε on x = 0..19, ε standard normal: the slope's sampling standard deviation is
  // σ / sqrt(Σ(x-x̄)²) = 0.1 / sqrt(665) = 3.878e-3, and the mean reported variance se² estimates it
  // without bias. Over 4000 replicas: the scatter of the slopes is a standard deviation from 4000 draws,
  // known to 1/sqrt(2·3999) = 1.1 % (checked at 3x that); each se² = s²/Σ(x-x̄)² has relative variance
  // 2/(n-2) = 1/9, so the rms of 4000 of them is known to sqrt(1/9/4000)/2 = 0.26 % (checked at 1 %);
  // the mean slope to 3 standard errors of the mean.
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> normal;
  const double sigma = 0.1, slope = -0.3;
  std::vector<double> x(20), y(20);
  double sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = double(i);
  for (double v : x) sxx += (v - 9.5) * (v - 9.5);
  const double expected = sigma / std::sqrt(sxx);
  const int replicas = 4000;
  double sum = 0, sum2 = 0, variance = 0;
  for (int r = 0; r < replicas; ++r) {
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = 0.5 + slope * x[i] + sigma * normal(rng);
    const LineFit fit = fit_line(x, y);
    sum += fit.slope, sum2 += fit.slope * fit.slope, variance += fit.slope_error * fit.slope_error;
  }
  const double mean = sum / replicas;
  const double spread = std::sqrt((sum2 - replicas * mean * mean) / (replicas - 1));
  INFO("expected se " << expected << ", scatter " << spread << ", rms reported se " << std::sqrt(variance / replicas));
  CHECK(std::abs(mean - slope) < 3 * expected / std::sqrt(double(replicas)));
  CHECK(spread == Approx(expected).epsilon(0.034));
  CHECK(std::sqrt(variance / replicas) == Approx(expected).epsilon(0.01));
}

TEST_CASE("least squares: degenerate input", "[fit]") {
  const std::vector<double> two{1, 3}, values{2, 6};
  const LineFit exact = fit_line(two, values);  // two points fix the line: no scatter, zero error
  CHECK(exact.slope == Approx(2.0));
  CHECK(exact.intercept == Approx(0.0).margin(1e-15));
  CHECK(exact.slope_error == 0.0);
  const std::vector<double> same{2, 2, 2}, any{1, 2, 3};
  CHECK_FALSE(fit_line(same, any).valid());  // all x equal: no slope
  CHECK(std::isnan(fit_line(same, any).slope));
  CHECK_FALSE(fit_line(std::vector<double>{1.0}, std::vector<double>{1.0}).valid());
  CHECK_THROWS_AS(fit_line(two, any), InputError);
}
