// Observables: names as written in scenes (the registry), evaluated on density and particle states, and
// what each needs of a state.
#include <catch2/catch.hpp>

#include <cmath>

#include "validation/observables/observable.hpp"

using namespace aggkit;

namespace {

// Four discs of radius 0.5 on a line, touching in pairs: clusters {0, 1} and {2, 3}; masses 1 and 3.
class TwoPairs final : public ParticleSource {
 public:
  ParticleConfiguration configuration() const override {
    ParticleConfiguration c;
    c.dimension = 2, c.radius = 0.5, c.box = {10, 10, 0}, c.periodic = false;
    c.positions = {{1, 1, 0}, {2, 1, 0}, {5, 1, 0}, {6, 1, 0}};
    return c;
  }
  std::vector<Vector3> velocities() const override { return {{1, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 2, 0}}; }
  std::vector<double> masses() const override { return {1, 1, 3, 3}; }
  std::vector<std::uint32_t> cluster_labels() const override {
    ++label_calls;
    return {0, 0, 1, 1};
  }
  mutable int label_calls = 0;
};

}  // namespace

TEST_CASE("observables: names M<p>, n<k> and the plain names of the registry") {
  const auto m15 = Observable::from_name("M1.5");
  REQUIRE(m15);
  CHECK(m15->type().form == "M<p>");
  CHECK(m15->parameter() == 1.5);
  CHECK(m15->name() == "M1.5");
  const auto n10 = Observable::from_name("n10");
  REQUIRE(n10);
  CHECK(n10->type().form == "n<k>");
  CHECK(n10->type().size_parameter);
  CHECK(n10->parameter() == 10);
  CHECK(Observable::from_name("mass_leak")->type().form == "mass_leak");
  CHECK(Observable::from_name("M0")->parameter() == 0.0);
  for (const char* bad : {"M", "M-1", "Mnan", "Minf", "M+1", "M1x", "n0", "n", "n-2", "n1.5", "N3", "m2", "", "mass"})
    CHECK_FALSE(Observable::from_name(bad));
  // Every registry entry is reachable by its own plain name (the parameterised forms aside).
  for (const ObservableType& type : observable_types())
    if (type.form.find('<') == std::string::npos) CHECK(Observable::from_name(type.form));
}

TEST_CASE("observables: evaluated on a density state") {
  // n = (0.5, 0.25, 0, 0.125): M0 = 0.875, M1 = 0.5 + 0.5 + 0.5 = 1.5, M2 = 0.5 + 1 + 2 = 3.5.
  const std::vector<double> n{0.5, 0.25, 0.0, 0.125};
  const DensityState state(n, 0.0625);
  CHECK(Observable::from_name("M0")->value(state) == 0.875);
  CHECK(Observable::from_name("M1")->value(state) == 1.5);
  CHECK(Observable::from_name("M2")->value(state) == 3.5);
  CHECK(Observable::from_name("M0.5")->value(state) == Approx(0.5 + 0.25 * std::sqrt(2.0) + 0.125 * 2.0));
  CHECK(Observable::from_name("n2")->value(state) == 0.25);
  CHECK(Observable::from_name("n7")->value(state) == 0.0);  // beyond the sizes held
  CHECK(Observable::from_name("mass_leak")->value(state) == 0.0625);
  CHECK(Observable::from_name("mean_cluster_size")->value(state) == Approx(1.5 / 0.875));
  CHECK(std::isnan(Observable::from_name("kinetic_energy")->value(state)));  // no particles
}

TEST_CASE("observables: evaluated on a particle state, computing only what is asked") {
  const TwoPairs source;
  const ParticleView view(source);
  CHECK(Observable::from_name("M0")->value(view) == 0.5);  // two clusters per four particles
  CHECK(Observable::from_name("n2")->value(view) == 0.5);
  CHECK(Observable::from_name("clusters")->value(view) == 2);
  CHECK(Observable::from_name("mean_cluster_size")->value(view) == 2);
  CHECK(Observable::from_name("largest_cluster")->value(view) == 2);
  // ½ (1 + 1) 1² + ½ (3 + 3) 2² = 1 + 12.
  CHECK(Observable::from_name("kinetic_energy")->value(view) == 13.0);
  CHECK(source.label_calls == 1);  // labels were asked once and then reused
  // Contacts within 2.1 R: pairs (0,1) and (2,3), each counted from both ends: 4 / (N N_max) = 4 / 24.
  CHECK(Observable::from_name("contacts")->value(view) == Approx(4.0 / 24.0));
  const auto fit = Observable::from_name("fractal_dimension_mass")->final_values(view);
  REQUIRE(fit.size() == 4);
  CHECK(fit[1].first == "fractal_dimension_mass_error");
  CHECK(Observable::from_name("pair_distribution")->is_profile());
  const Profile p = Observable::from_name("pair_distribution")->profile(view);
  CHECK(p.x.size() == 90);
  CHECK(p.y.back() == Approx(3.0));  // every pair lies within 20 R = 10: 3 other particles each
}

TEST_CASE("observables: needs say what a state must give") {
  CHECK(Observable::from_name("M2")->needs() == need::sizes);
  CHECK(Observable::from_name("mass_leak")->needs() == need::leaked_mass);
  CHECK((Observable::from_name("kinetic_energy")->needs() & need::velocities));
  CHECK((Observable::from_name("kinetic_energy")->needs() & ~need::kinetic) != 0);  // kinetic engines cannot give it
  CHECK((Observable::from_name("M2")->needs() & ~need::particles) == 0);          // particle engines can
  CHECK(describe_needs(need::velocities | need::masses) == "particle velocities, particle masses");
}
