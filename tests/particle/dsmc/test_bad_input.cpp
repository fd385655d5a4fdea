// Bad DSMC input gets an InputError naming the key, the value and what is allowed.
#include <catch2/catch.hpp>

#include "analysis/input_error.hpp"
#include "tests/particle/dsmc/dsmc_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

TEST_CASE("dsmc: bad options and models are refused with the key named") {
  const AggregationModel model = aggkit::testing::dsmc_model(Kernel::constant(), 0.1);
  dsmc::Options options;
  options.particles = 1;
  CHECK_THROWS_WITH(dsmc::Simulation(model, options, 1, 1.0), Contains("particles = 1") && Contains("an integer in 2.."));
  options = {};
  options.bucket = 0;
  CHECK_THROWS_WITH(dsmc::Simulation(model, options, 1, 1.0), Contains("bucket = 0") && Contains("an integer in 1.."));
  options = {};
  options.runs = 0;
  CHECK_THROWS_WITH(dsmc::Ensemble(model, options, 1.0), Contains("runs = 0"));
  CHECK_THROWS_WITH(dsmc::method_from_name("gillespie"), Contains("method = \"gillespie\"") && Contains("gillespie"));
  AggregationModel negative = model;
  negative.lambda = ShatteringRate::constant(-0.5);
  CHECK_THROWS_AS(dsmc::Simulation(negative, dsmc::Options{}, 1, 1.0), InputError);
  CHECK_THROWS_WITH(dsmc::Simulation(negative, dsmc::Options{}, 1, 1.0), Contains("lambda = -0.5"));
}

TEST_CASE("dsmc: bad engine options in a scene name the scene key") {
  const auto scene = [](const std::string& engine, const std::string& lambda = "0.1") {
    return "name = \"x\"\n[model]\nkernel = { name = \"constant\" }\nlambda = " + lambda +
           "\nsize = 16\n[time]\nend = 1.0\n[[engine]]\nname = \"dsmc\"\n" + engine +
           "\n[observe]\nseries = [\"M0\"]\n";
  };
  CHECK_NOTHROW(aggkit::testing::parse_checked(scene("particles = 100\nruns = 2\nbucket = 4\nmethod = \"fast\"\nseed = 7")));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("particles = 1")), Contains("engine[0].particles = 1"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("bucket = 0")), Contains("engine[0].bucket = 0"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("runs = 0")), Contains("engine[0].runs = 0"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("method = \"exact\"")), Contains("engine[0].method"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("particles = 100", "-0.5")), Contains("model.lambda = -0.5"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene("colour = 1")), Contains("colour"));
}
