// Steady states by continuation in λ (solvers/steady_branch.hpp): the same root as a direct solve where both
// run, independent of the order the λ values are asked in, roots where the solver's own start fails, and
// clear errors for a bad anchor or step.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/steady_branch.hpp"

using namespace aggkit;

namespace {

AggregationModel brownian(double a, std::size_t N, SizeGrid grid = {}) {
  AggregationModel model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(0.1);
  model.size = N;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid = grid;
  return model;
}

double max_relative_difference(const std::vector<double>& x, const std::vector<double>& y) {
  double largest = 0.0, difference = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    largest = std::max(largest, std::abs(x[k]));
    difference = std::max(difference, std::abs(x[k] - y[k]));
  }
  return difference / largest;
}

}  // namespace

TEST_CASE("continuation in lambda reaches the root a direct solve finds", "[snes][steady][branch]") {
  // a = 0.9, N = 1024 at λ = 0.03: the solver's own CVODE start converges there too. Both roots balance to the
  // Newton tolerance (relative residual 1e-10), so they agree to well within 1e-7 of the largest density.
  const AggregationModel model = brownian(0.9, 1024);
  SteadyBranch branch(model, 0.1);
  const BranchSteadyState walked = branch.at(0.03);
  REQUIRE(walked.steady.converged);
  CHECK(walked.how.find("continuation from lambda = 0.1") != std::string::npos);
  CHECK(walked.steps == 4);  // nodes 0.1 e^{-0.5}, 0.1 e^{-1}, then 0.03 (after the anchor's own solve)
  AggregationModel at = model;
  at.lambda = ShatteringRate::constant(0.03);
  const SteadyStateResult direct = solve_steady_state(at);
  REQUIRE(direct.converged);
  CHECK(max_relative_difference(walked.steady.n, direct.n) < 1e-7);
  // At or above the anchor: the direct solve itself.
  const BranchSteadyState high = branch.at(0.2);
  REQUIRE(high.steady.converged);
  CHECK(high.how == "newton from a CVODE start");
}

TEST_CASE("a branch's root at lambda does not depend on what was asked before", "[snes][steady][branch]") {
  // Scan points run in any order on any number of ranks: the ladder's nodes are fixed, so a state reached
  // after other λ values is the same to the bit as from a fresh branch.
  const AggregationModel model = brownian(0.8, 512);
  SteadyBranch first(model, 0.1), second(model, 0.1);
  const BranchSteadyState deep = first.at(0.004);
  const BranchSteadyState then = first.at(0.02);
  const BranchSteadyState fresh = second.at(0.02);
  REQUIRE(deep.steady.converged);
  REQUIRE(then.steady.converged);
  REQUIRE(fresh.steady.converged);
  CHECK(then.steady.n == fresh.steady.n);
  CHECK(then.steps == fresh.steps);
}

TEST_CASE("continuation on a coarse graded grid: the direct solve's root, then where the roots go negative", "[snes][steady][branch]") {
  // a = 0.7 on K = 16, r = 1.1 up to N = 2^34 (about 150 classes) with three-moment shares. At λ = 1e-5 the
  // solver's own start (a CVODE relaxation) still converges, and the walk down from 0.1 (24 Newton solves)
  // lands on the same root. Far below, this coarse grid has no positive root (the steep front undershoots):
  // at λ = 1e-9 the walk stops above, saying where and that the next root has negative densities. Four-moment
  // shares (the default) have a positive root there on the same grid.
  SizeGrid grid;
  grid.resolved = 16;
  grid.ratio = 1.1;
  grid.scheme = GridScheme::three_moment;
  AggregationModel model = brownian(0.7, std::size_t(1) << 34, grid);
  SteadyBranch branch(model, 0.1);
  const BranchSteadyState walked = branch.at(1e-5);
  INFO(walked.note);
  REQUIRE(walked.steady.converged);
  CHECK(walked.steady.most_negative_density >= -1e-8);  // the solver's own limits on a positive root
  CHECK(walked.steady.negative_mass_fraction <= 1e-6);
  CHECK(walked.steady.relative_residual < 1e-8);
  CHECK(std::isnan(walked.stopped_lambda));
  model.lambda = ShatteringRate::constant(1e-5);
  const SteadyStateResult direct = solve_steady_state(model);
  REQUIRE(direct.converged);
  CHECK(max_relative_difference(walked.steady.n, direct.n) < 1e-6);

  const BranchSteadyState deep = branch.at(1e-9);
  CHECK_FALSE(deep.steady.converged);
  CHECK(deep.negative_root);
  CHECK(deep.stopped_lambda > 1e-9);
  CHECK(deep.stopped_lambda < 1e-5);
  CHECK_THAT(deep.note, Catch::Contains("negative densities"));

  AggregationModel four = brownian(0.7, std::size_t(1) << 34, grid);
  four.grid.scheme = GridScheme::four_moment;
  const BranchSteadyState reached = SteadyBranch(four, 0.1).at(1e-9);
  INFO(reached.note);
  REQUIRE(reached.steady.converged);
  CHECK(reached.steady.most_negative_density >= -1e-8);
  CHECK(reached.steady.relative_residual < 1e-8);
}

TEST_CASE("a steady branch refuses a bad anchor, step or lambda", "[snes][steady][branch]") {
  const AggregationModel model = brownian(0.9, 64);
  CHECK_THROWS_AS(SteadyBranch(model, 0.0), InputError);
  CHECK_THROWS_AS(SteadyBranch(model, NAN), InputError);
  CHECK_THROWS_AS(SteadyBranch(model, 0.1, 0.0), InputError);
  CHECK_THROWS_AS(SteadyBranch(model, 0.1, 3.0), InputError);
  SteadyBranch branch(model, 0.1);
  CHECK_THROWS_AS(branch.at(-1.0), InputError);
  CHECK_THROWS_WITH(branch.at(0.0), Catch::Contains("lambda"));
}
