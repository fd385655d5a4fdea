// Population halving (particle/dsmc/population_control.hpp): exact per-size bounds and the unbiased expected
// counts of one halving, and whole runs through several halvings against the exact total density of the
// constant kernel with shattering and against CVODE.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "analysis/moments.hpp"
#include "particle/dsmc/binned_population.hpp"
#include "particle/dsmc/population_control.hpp"
#include "solvers/cvode_integrator.hpp"
#include "tests/particle/dsmc/dsmc_fixture.hpp"

using namespace aggkit;

namespace {

std::map<std::uint64_t, std::uint64_t> counts_of(const dsmc::BinnedPopulation& population) {
  std::map<std::uint64_t, std::uint64_t> counts;
  population.for_each_group([&](std::uint64_t s, std::uint64_t n) { counts[s] += n; });
  return counts;
}

// K = 1 with shattering rate λ: dM0/dt = λ M0 − (1+2λ)/2 M0² (each aggregation removes one particle, each
// shattering of i + j adds i + j − 2, and M1 = 1), a logistic towards M* = 2λ/(1+2λ).
double logistic_total_density(double lambda, double m0_start, double t) {
  const double target = 2.0 * lambda / (1.0 + 2.0 * lambda);
  return target / (1.0 + (target / m0_start - 1.0) * std::exp(-lambda * t));
}

}  // namespace

TEST_CASE("dsmc: a halving keeps floor or ceil of half of every size, and half the mass up to the odd ones") {
  // Bucketed sizes (<= 8) and individually stored ones (> 8), odd and even counts, repeated large sizes.
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> start{{1, 1001}, {2, 40}, {3, 7}, {8, 1},
                                                                   {9, 3},    {13, 2}, {40, 5}, {1000, 1}};
  std::map<std::uint64_t, double> mean_kept;
  const int trials = 4000;
  for (int seed = 0; seed < trials; ++seed) {
    dsmc::BinnedPopulation population(8);
    std::uint64_t mass = 0, odd_mass = 0;
    for (const auto& [s, n] : start) {
      population.add(s, n);
      mass += s * n;
      if (n % 2 == 1) odd_mass += s;
    }
    dsmc::Random random(std::uint64_t(seed) + 1);
    population.halve(random);
    const auto counts = counts_of(population);
    std::uint64_t kept_mass = 0, kept = 0;
    for (const auto& [s, n] : start) {
      const std::uint64_t k = counts.count(s) ? counts.at(s) : 0;
      REQUIRE((k == n / 2 || k == (n + 1) / 2));
      kept_mass += s * k;
      kept += k;
      mean_kept[s] += double(k) / trials;
    }
    REQUIRE(population.particles() == kept);
    // |2 × kept mass − mass| <= Σ sizes of the odd ones out (each kept or not).
    REQUIRE(std::abs(2.0 * double(kept_mass) - double(mass)) <= double(odd_mass));
    // The picked particles of every bin are the kept ones (bin counts and the Fenwick tree were rebuilt).
    std::map<std::uint64_t, std::uint64_t> picked;
    for (std::size_t b = 0; b < population.bins(); ++b)
      for (std::uint64_t r = 0; r < population.count(b); ++r) ++picked[population.pick(b, r).size];
    REQUIRE(picked == counts);
  }
  // Unbiased: an odd count n keeps n/2 on average. The mean over 4000 halvings of floor(n/2) + coin has
  // standard deviation 0.5/sqrt(4000) = 0.008; 5 of those (P ~ 6e-7 per size).
  for (const auto& [s, n] : start) {
    INFO("size " << s << ", count " << n);
    CHECK(std::abs(mean_kept[s] - double(n) / 2.0) <= 5.0 * 0.5 / std::sqrt(double(trials)));
  }
}

TEST_CASE("dsmc: runs through several halvings follow the exact total density of K = 1 with shattering") {
  // Octamers only (M0(0) = 1/8, M1 = 1), λ = 1: shattering drives M0 up to M* = 2/3, so the particle count
  // grows 5.3x and every run halves at least twice by t = 6.
  const double lambda = 1.0;
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::constant(), lambda, 256);
  model.initial.assign(256, 0.0);
  model.initial[7] = 1.0 / 8.0;
  const std::vector<double> times{1.0, 3.0, 6.0};
  // Independent reference for M2: CVODE on sizes <= 256 (shattering at λ = 1 keeps the mass beyond 256
  // below 1e-12 up to t = 6).
  std::vector<double> reference_m2;
  IntegratorOptions tight;
  tight.rtol = 1e-9;
  integrate(model, times, tight, [&](double, std::span<const double> n, double) { reference_m2.push_back(moment(n, 2.0)); });
  for (const auto method : {dsmc::Method::acceptance_rejection, dsmc::Method::fast}) {
    dsmc::Options options;
    options.method = method;
    options.particles = 3000;
    options.runs = 16;
    options.seed = 21;
    options.population_halving = true;  // off by default
    dsmc::Ensemble ensemble(model, options, times.back());
    for (std::size_t i = 0; i < times.size(); ++i) {
      std::vector<double> m0, m1, m2;
      for (const auto& s : ensemble.advance_to(times[i])) {
        m0.push_back(s.moment(0.0));
        m1.push_back(s.moment(1.0));
        m2.push_back(s.moment(2.0));
      }
      const auto e0 = dsmc::mean_and_error(m0), e1 = dsmc::mean_and_error(m1), e2 = dsmc::mean_and_error(m2);
      const double exact = logistic_total_density(lambda, 1.0 / 8.0, times[i]);
      INFO("method " << dsmc::to_string(method) << ", t = " << times[i] << ": M0 " << e0.mean << " ± "
                     << e0.standard_error << " vs " << exact << ", M1 " << e1.mean << " ± " << e1.standard_error
                     << ", M2 " << e2.mean << " ± " << e2.standard_error << " vs " << reference_m2[i]);
      // 5 standard errors of a 16-run mean (t-distribution, 15 degrees of freedom: P(|t| > 5) ~ 2e-4 per
      // check) plus 0.5 % for the O(1/N) bias of 3000 particles (N(0)/8 clusters at the start).
      CHECK(std::abs(e0.mean - exact) <= 5.0 * e0.standard_error + 5e-3 * exact);
      CHECK(std::abs(e1.mean - 1.0) <= 5.0 * e1.standard_error + 1e-12);  // the mass, kept in expectation
      CHECK(std::abs(e2.mean - reference_m2[i]) <= 5.0 * e2.standard_error + 5e-3 * reference_m2[i]);
    }
    for (std::size_t r = 0; r < ensemble.runs(); ++r) {
      const auto& run = ensemble.run(r);
      CHECK(run.statistics().halvings >= 2);
      CHECK(run.statistics().doublings == 0);
      CHECK(run.snapshot().particles <= 2 * options.particles);
      CHECK(run.mass() == run.control_mass());  // exact between population-control events
    }
  }
}

TEST_CASE("dsmc: without population_halving the shattering population only grows") {
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::constant(), 1.0, 256);
  model.initial.assign(256, 0.0);
  model.initial[7] = 1.0 / 8.0;
  dsmc::Options options;
  options.particles = 3000;
  options.population_halving = false;
  dsmc::Simulation simulation(model, options, 5, 6.0);
  simulation.advance_to(6.0);
  CHECK(simulation.statistics().halvings == 0);
  CHECK(simulation.snapshot().particles > 4 * options.particles);  // M0 grew from 1/8 to ~2/3: 5.3x
  CHECK(simulation.mass() == simulation.initial_mass());           // no control event: the mass is exact
}
