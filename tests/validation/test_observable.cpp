// Observables: names as written in scenes, evaluated on a state.
#include <catch2/catch.hpp>

#include <cmath>

#include "validation/observables/observable.hpp"

using namespace aggkit;

TEST_CASE("scene: observable names M<p>, n<k> and mass_leak") {
  const auto m15 = Observable::from_name("M1.5");
  REQUIRE(m15);
  CHECK(m15->kind() == Observable::Kind::moment);
  CHECK(m15->order() == 1.5);
  CHECK(m15->name() == "M1.5");
  const auto n10 = Observable::from_name("n10");
  REQUIRE(n10);
  CHECK(n10->kind() == Observable::Kind::density);
  CHECK(n10->size() == 10);
  CHECK(Observable::from_name("mass_leak")->kind() == Observable::Kind::mass_leak);
  CHECK(Observable::from_name("M0")->order() == 0.0);
  for (const char* bad : {"M", "M-1", "Mnan", "Minf", "M+1", "M1x", "n0", "n", "n-2", "n1.5", "N3", "m2", "", "mass"})
    CHECK_FALSE(Observable::from_name(bad));
}

TEST_CASE("scene: observables evaluated on a density state") {
  // n = (0.5, 0.25, 0, 0.125): M0 = 0.875, M1 = 0.5 + 0.5 + 0.5 = 1.5, M2 = 0.5 + 1 + 2 = 3.5.
  const std::vector<double> n{0.5, 0.25, 0.0, 0.125};
  const DensityState state(n, 0.0625);
  CHECK(Observable::from_name("M0")->evaluate(state) == 0.875);
  CHECK(Observable::from_name("M1")->evaluate(state) == 1.5);
  CHECK(Observable::from_name("M2")->evaluate(state) == 3.5);
  CHECK(Observable::from_name("M0.5")->evaluate(state) == Approx(0.5 + 0.25 * std::sqrt(2.0) + 0.125 * 2.0));
  CHECK(Observable::from_name("n2")->evaluate(state) == 0.25);
  CHECK(Observable::from_name("n7")->evaluate(state) == 0.0);  // beyond the sizes held
  CHECK(Observable::from_name("mass_leak")->evaluate(state) == 0.0625);
}
