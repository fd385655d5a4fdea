// Progress lines: engine, time reached / end and elapsed time; nothing when quiet.
#include <catch2/catch.hpp>

#include <sstream>

#include "validation/io/progress.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

TEST_CASE("harness: progress names the engine and the time reached, and is silent when quiet") {
  std::ostringstream out;
  Progress progress(&out, std::chrono::seconds(0));
  progress.start("cvode", 1, 2, 100.0);
  progress.reached(25.0);
  progress.finish();
  CHECK_THAT(out.str(), Contains("engine 1/2 cvode") && Contains("t = 25 / 100 (25%)") && Contains("done in"));

  std::ostringstream words;
  Progress stages(&words, std::chrono::seconds(0));
  stages.start("ed", 1, 1, 10.0);
  stages.note("thermalising: 12 of 100 particles have 10 collisions");
  CHECK_THAT(words.str(), Contains("aggkit: engine 1/1 ed: thermalising: 12 of 100 particles have 10 collisions, ") &&
                              Contains(" s\n"));

  std::ostringstream throttled;
  Progress slow(&throttled, std::chrono::hours(1));
  slow.start("exact", 2, 2, 1.0);
  slow.reached(0.5);
  slow.note("a stage");
  slow.finish();
  CHECK(throttled.str().empty());  // short runs print nothing

  Progress quiet(nullptr);
  quiet.start("cvode", 1, 1, 1.0);
  quiet.reached(1.0);
  quiet.finish();  // no stream to write to: nothing happens
}
