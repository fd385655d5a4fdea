// λ_crit(a) from the regimes of a scan grid: the bracket between the largest sustained λ and the next
// relaxing one, its midpoint and error bound.
#include <catch2/catch.hpp>

#include <cmath>

#include "validation/scan/scan_lambda_crit.hpp"

using namespace aggkit;

namespace {
ScanRecord point(double lambda, const char* regime) {
  ScanRecord r;
  r.a = 0.9;
  r.lambda = lambda;
  r.regime = regime;
  r.converged = true;
  return r;
}
}  // namespace

TEST_CASE("scan lambda_crit: the bracket's midpoint, arithmetic or geometric, with the half width as error") {
  const std::vector<ScanRecord> grid{point(0.04, "damped"), point(0.01, "sustained"), point(0.02, "sustained"),
                                     point(0.03, "damped"), point(0.05, "steady")};
  const GridLambdaCrit linear = lambda_crit_from_grid(0.9, grid, false);
  CHECK(linear.lambda_sustained == 0.02);
  CHECK(linear.lambda_relaxing == 0.03);
  CHECK(linear.lambda_crit == Approx(0.025).epsilon(1e-14));
  CHECK(linear.error == Approx(0.005).epsilon(1e-12));
  CHECK(linear.note.empty());
  const GridLambdaCrit log = lambda_crit_from_grid(0.9, grid, true);
  CHECK(log.lambda_crit == Approx(std::sqrt(0.02 * 0.03)).epsilon(1e-14));
  CHECK(log.lambda_crit + log.error == Approx(0.03).epsilon(1e-14));  // the bracket is within the error
  CHECK(log.lambda_crit - log.error <= 0.02);
}

TEST_CASE("scan lambda_crit: no bracket on the grid, and non-monotone grids, are reported") {
  const GridLambdaCrit none = lambda_crit_from_grid(0.9, {point(0.01, "damped"), point(0.02, "steady")}, false);
  CHECK(std::isnan(none.lambda_crit));
  CHECK(none.note.find("lambda_crit < 0.01") != std::string::npos);
  const GridLambdaCrit all = lambda_crit_from_grid(0.9, {point(0.01, "sustained"), point(0.02, "sustained")}, false);
  CHECK(std::isnan(all.lambda_crit));
  CHECK(all.note.find("lambda_crit > 0.02") != std::string::npos);
  const GridLambdaCrit odd = lambda_crit_from_grid(
      0.9, {point(0.01, "damped"), point(0.02, "sustained"), point(0.03, "irregular"), point(0.04, "damped")}, false);
  CHECK(odd.lambda_crit == Approx(0.03).epsilon(1e-14));  // the irregular point says nothing
  CHECK(odd.note.find("not monotone") != std::string::npos);
  CHECK(odd.note.find("1 points without a converged verdict") != std::string::npos);
  // A tentative sustained verdict (e.g. a long-period transient with too few cycles) is not a bracket end.
  ScanRecord tentative = point(0.03, "sustained");
  tentative.converged = false;
  const GridLambdaCrit t = lambda_crit_from_grid(0.9, {point(0.01, "sustained"), point(0.02, "damped"), tentative}, false);
  CHECK(t.lambda_crit == Approx(0.015).epsilon(1e-14));
}
