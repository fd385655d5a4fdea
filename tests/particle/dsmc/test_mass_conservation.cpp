// Exact (integer) mass conservation of DSMC through aggregation, shattering and population doubling:
// mass(t) = mass(0) · 2^doublings at every output, for both methods and any bucket size. (A halving keeps
// the mass in expectation only: tests/particle/dsmc/test_population_control.cpp.)
#include <catch2/catch.hpp>

#include "tests/particle/dsmc/dsmc_fixture.hpp"

using namespace aggkit;

TEST_CASE("dsmc: mass is conserved exactly through shattering and cloning") {
  for (const auto method : {dsmc::Method::acceptance_rejection, dsmc::Method::fast})
    for (const std::uint64_t bucket : {1ULL, 8ULL, 1024ULL}) {
      INFO("method " << dsmc::to_string(method) << ", bucket " << bucket);
      dsmc::Options options;
      options.method = method;
      options.particles = 1500;
      options.bucket = bucket;
      options.seed = 3;
      // Ballistic kernel with shattering (λ = 0.02): the count falls to a few per cent of N(0) by t = 10
      // (several doublings) while shattering events return whole clusters to monomers.
      AggregationModel model = aggkit::testing::dsmc_model(Kernel::ballistic(), 0.02, 16);
      dsmc::Simulation simulation(model, options, 42, 10.0);
      const std::uint64_t mass0 = simulation.initial_mass();
      CHECK(mass0 == simulation.snapshot().mass());
      for (double t : {1.0, 2.0, 5.0, 10.0}) {
        simulation.advance_to(t);
        const auto& s = simulation.statistics();
        REQUIRE(s.halvings == 0);  // the count only falls here
        CHECK(simulation.mass() == (mass0 << s.doublings));
        CHECK(simulation.control_mass() == (mass0 << s.doublings));
        CHECK(simulation.snapshot().mass() == (mass0 << s.doublings));  // no `drop` truncation: nothing leaked
      }
      CHECK(simulation.statistics().shatterings > 0);
      CHECK(simulation.statistics().doublings > 0);
      // Densities are unchanged by a doubling: M1 stays the initial mass density, 1.
      CHECK(simulation.snapshot().moment(1.0) == Approx(1.0).epsilon(1e-12));
    }
}

TEST_CASE("dsmc: the drop truncation counts the mass it removes") {
  dsmc::Options options;
  options.particles = 2000;
  options.truncate = true;
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::constant(), 0.0, 8);
  dsmc::Simulation simulation(model, options, 9, 20.0);
  simulation.advance_to(20.0);
  const auto s = simulation.snapshot();
  CHECK(s.leaked_mass > 0);
  CHECK(s.mass() + s.leaked_mass == (simulation.initial_mass() << simulation.statistics().doublings));
  CHECK(s.groups.back().first <= 8);  // nothing larger than N stays
}

TEST_CASE("dsmc: one cluster left is reported as extinction, not looped on") {
  dsmc::Options options;
  options.particles = 2;
  options.population_control = false;
  dsmc::Simulation simulation(aggkit::testing::dsmc_model(Kernel::constant(), 0.0), options, 1, 1e6);
  simulation.advance_to(1e6);
  CHECK(simulation.statistics().extinct);
  CHECK(simulation.statistics().frozen_time < 1e6);
  CHECK(simulation.snapshot().particles == 1);
  CHECK(simulation.snapshot().mass() == 2);
}

TEST_CASE("dsmc: a population with every pair beyond the cutoff is frozen") {
  dsmc::Options options;
  options.particles = 64;
  options.truncate = true;
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::constant(), 0.0, 4);
  model.truncation = Truncation::cutoff;
  model.initial = {0.0, 0.0, 1.0};  // trimers only: 3 + 3 > 4
  dsmc::Simulation simulation(model, options, 1, 100.0);
  simulation.advance_to(100.0);
  CHECK(simulation.statistics().frozen);
  CHECK_FALSE(simulation.statistics().extinct);
  CHECK(simulation.statistics().accepted() == 0);
}
