// Observables: names as written in scenes (the registry), evaluated on density and particle states, and
// what each needs of a state.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

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

namespace {

const double two_pi = 2 * std::acos(-1.0);

struct Sampled {
  std::vector<double> t, x;
};

Sampled sample(double end, const std::function<double(double)>& f) {  // Δt = 1, as the oscillation scenes
  Sampled s;
  for (double t = 0; t <= end + 1e-12; t += 1.0) s.t.push_back(t), s.x.push_back(f(t));
  return s;
}

double measure(const std::string& name, const Sampled& s) { return Observable::from_name(name)->measure(s.t, s.x); }

}  // namespace

TEST_CASE("observables: oscillation measures of a series against sines whose measures are known exactly") {
  const auto period = Observable::from_name("oscillation_period:M0");
  REQUIRE(period);
  CHECK(period->is_series_measure());
  CHECK(period->source() == "M0");
  CHECK(period->needs() == 0);  // taken of the series: any engine can give it
  CHECK(Observable::from_name("oscillation_amplitude:mean_cluster_size")->source() == "mean_cluster_size");
  CHECK_FALSE(Observable::from_name("oscillation_period:"));
  CHECK_FALSE(Observable::from_name("M0")->is_series_measure());

  SECTION("a sustained sine: period, half peak-to-peak and rms amplitude, mean") {
    // T = 33.7 sampled at Δt = 1 (the a = 0.95 limit cycle's period and sampling): the parabolic refinement
    // of the turning points is exact to O((Δt/T)^4) ~ 1e-6; the mean over a window that is not a whole
    // number of cycles is off by at most A/(π · cycles) ~ 1e-3 of the amplitude.
    const Sampled s = sample(800, [](double t) { return 0.14 + 0.075 * std::sin(two_pi * t / 33.7 + 1.0); });
    CHECK(measure("oscillation_period:M0", s) == Approx(33.7).epsilon(1e-4));
    CHECK(measure("oscillation_amplitude:M0", s) == Approx(0.075).epsilon(1e-4));
    // Over whole cycles between turning points sampled at Δt = 1: the sampled variance of a sine over a
    // whole number of periods is exact up to the partial sample at the ends, < 1/(cycles · T/Δt) ~ 1e-3.
    CHECK(measure("oscillation_rms:M0", s) == Approx(0.075).epsilon(2e-3));
    CHECK(measure("oscillation_mean:M0", s) == Approx(0.14).epsilon(1e-3));
  }
  SECTION("a damped sine: period exactly T, amplitude the mean of its analytic half swings") {
    // x = e^{-γt} A sin(ωt): its extremes lie at ωt_n = atan(ω/γ) + nπ with |x| = A e^{-γ t_n} ω/sqrt(ω²+γ²),
    // exactly T/2 apart, so the mean spacing of same-kind turning points is T and each cycle amplitude is
    // ½ (|x(t_n)| + |x(t_{n+1})|). The series ends a quarter period after an extreme (it reverses there).
    const double A = 0.3, T = 20.0, w = two_pi / T, g = 0.002;
    const double t0 = std::atan(w / g) / w;
    const double end = std::round(t0 + 29 * T / 2 + T / 4);
    const Sampled s = sample(end, [&](double t) { return A * std::exp(-g * t) * std::sin(w * t); });
    std::vector<double> extremes;
    for (double t = t0; t < end - T / 8; t += T / 2) extremes.push_back(A * std::exp(-g * t) * w / std::hypot(w, g));
    double expected = 0;
    for (std::size_t n = 0; n + 1 < extremes.size(); ++n) expected += 0.5 * (extremes[n] + extremes[n + 1]);
    expected /= double(extremes.size() - 1);
    CHECK(measure("oscillation_period:M0", s) == Approx(T).epsilon(1e-3));  // refinement error ~(Δt/T)^4 ~ 1e-5
    CHECK(measure("oscillation_amplitude:M0", s) == Approx(expected).epsilon(1e-3));
  }
  SECTION("noise of 4 % of the half swing makes no spurious cycles, and the rms amplitude barely sees it") {
    // The DSMC case: M0 of 3·10^4 particles carries Gaussian noise of sd 0.003 on a half swing of 0.075.
    std::mt19937_64 random(7);
    std::normal_distribution<double> noise(0.0, 0.003);
    const Sampled s = sample(800, [&](double t) { return 0.14 + 0.075 * std::sin(two_pi * t / 33.7) + noise(random); });
    // 23 cycles: a spurious cycle would shift the mean period by ~4 %; the remaining error is the timing
    // jitter of the end points, ~sd/slope = 0.003/(0.075 ω) ~ 0.2 time units over 23 cycles.
    CHECK(measure("oscillation_period:M0", s) == Approx(33.7).epsilon(0.01));
    // Peaks are biased up by about one noise sd (0.003, 4 %); the rms amplitude only by sd²/(2A²) ~ 0.1 %,
    // with a sampling error of the cross term signal × noise of √2 sd/(A √n) ~ 0.2 % (n ~ 800 samples).
    CHECK(measure("oscillation_amplitude:M0", s) > 0.075);
    CHECK(measure("oscillation_rms:M0", s) == Approx(0.075).epsilon(0.01));
  }
  SECTION("no oscillation: NaN") {
    CHECK(std::isnan(measure("oscillation_period:M0", sample(100, [](double t) { return std::exp(-t / 10); }))));
    CHECK(std::isnan(measure("oscillation_amplitude:M0", sample(100, [](double) { return 1.0; }))));
  }
}
