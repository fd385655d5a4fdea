// Bad DSMC input gets an InputError naming the key, the value and what is allowed; a damaged saved state a CheckpointError.
#include <catch2/catch.hpp>

#include <cstring>
#include <string>

#include "analysis/input_error.hpp"
#include "particle/common/checkpoint.hpp"
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

TEST_CASE("dsmc: a saved state with a damaged length anywhere is refused with a CheckpointError") {
  // 2^62 written over each 8-byte-aligned word of a saved run in turn (both methods, bucketed and one-by-one
  // sizes): a length among them must be refused before anything is allocated for it. A length taken on trust
  // throws length_error or bad_alloc instead, which the harness does not turn into the refusal of a bad
  // checkpoint (exit status 2, the reason named). Every length of a run's state lies on such a word: all that
  // comes before the last of them (the stepper's vectors) is 8-byte values and length-prefixed 8-byte
  // vectors. Values that are not lengths may be read as they are. One run: a second would start 1 byte off
  // (the stepper's dirty flag), and each damaged state is restored into a fresh ensemble.
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::ballistic(), 0.1);
  model.truncation = Truncation::cutoff;
  for (const auto method : {dsmc::Method::acceptance_rejection, dsmc::Method::fast}) {
    dsmc::Options options;
    options.method = method;
    options.particles = 100;
    options.runs = 1;
    options.bucket = 8;
    options.threads = 1;
    dsmc::Ensemble ensemble(model, options, 1.0);
    ensemble.advance_to(0.5);
    StateWriter out;
    ensemble.save(out);
    const std::string good = out.take();
    std::size_t refused = 0;
    std::string other;  // the first exception of another kind, with where the damage was
    for (std::size_t at = 0; at + 8 <= good.size() && other.empty(); at += 8) {
      std::string bad = good;
      const std::uint64_t huge = std::uint64_t(1) << 62;
      std::memcpy(bad.data() + at, &huge, sizeof huge);
      dsmc::Ensemble fresh(model, options, 1.0);
      StateReader in(bad);
      try {
        fresh.restore(in);
        in.expect_end();
      } catch (const CheckpointError&) {
        ++refused;
      } catch (const std::exception& e) {
        other = "byte " + std::to_string(at) + " of " + std::to_string(good.size()) + ": " + e.what();
      }
    }
    INFO("method " << int(method));
    CHECK(other == "");
    CHECK(refused > 0);
  }
}
