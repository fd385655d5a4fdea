// Radius and mass laws: sample moments against the analytic ones, truncated moments against an independent
// quadrature, GSL expectations against Monte Carlo, and the messages of bad laws.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "analysis/input_error.hpp"
#include "particle/common/property_law.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

// Sample mean and standard deviation with their standard errors (the error of s from the fourth central
// moment: Var(s²) ≈ (μ4 − σ⁴)/n, so se(s) ≈ sqrt((μ4 − s⁴)/n) / (2s)).
struct Moments {
  double mean = 0, sd = 0, mean_error = 0, sd_error = 0;
};
Moments moments(const std::vector<double>& x) {
  const double n = double(x.size());
  Moments m;
  for (double v : x) m.mean += v / n;
  double m2 = 0, m4 = 0;
  for (double v : x) {
    const double d = v - m.mean;
    m2 += d * d / n;
    m4 += d * d * d * d / n;
  }
  m.sd = std::sqrt(m2 * n / (n - 1));
  m.mean_error = m.sd / std::sqrt(n);
  m.sd_error = std::sqrt((m4 - m2 * m2) / n) / (2 * m.sd);
  return m;
}

// ∫_a^b f by composite Simpson with n (even) panels: an oracle independent of GSL.
template <class F>
double simpson(F f, double a, double b, int n = 20000) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * f(a + i * h);
  return sum * h / 3;
}

double normal_density(double x, double mean, double sd) {
  const double z = (x - mean) / sd;
  return std::exp(-0.5 * z * z) / (sd * std::sqrt(2 * std::numbers::pi));
}

PropertyLaw law(Distribution kind, double mean, double sd, double min, double max) {
  PropertyLaw p;
  p.distribution = kind;
  p.mean = mean;
  p.sd = sd;
  p.min = min;
  p.max = max;
  return p;
}

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr std::size_t samples = 20000;

void check_sample(const PropertyLaw& p, double mean, double sd, std::uint64_t seed) {
  const std::vector<double> x = p.draw(samples, seed);
  for (double v : x) {
    REQUIRE(v >= p.min);
    REQUIRE(v <= p.max);
  }
  const Moments m = moments(x);
  INFO(p.describe() << ": sample mean " << m.mean << " ± " << m.mean_error << ", sd " << m.sd << " ± " << m.sd_error);
  CHECK(std::abs(m.mean - mean) < 4 * m.mean_error);
  CHECK(std::abs(m.sd - sd) < 4 * m.sd_error);
}

}  // namespace

TEST_CASE("normal, lognormal and uniform radii have the analytic mean and sd", "[particles][property_law]") {
  // Normal truncated 5 sd below the mean: the cut removes 2.9e-7 of the law, which moves the mean by about
  // 1.5e-7 sd, far below the standard error 0.1/sqrt(20000) = 7e-4: the untruncated moments apply.
  const PropertyLaw normal = law(Distribution::normal, 1.0, 0.1, 0.5, inf);
  check_sample(normal, 1.0, 0.1, 11);
  // The truncated mean exactly: m + s φ(α)/(1 − Φ(α)) with α = (min − m)/s = −5, i.e. 1 + 0.1 φ(5)/Φ(5).
  const double phi5 = std::exp(-12.5) / std::sqrt(2 * std::numbers::pi), upper_tail = 0.5 * std::erfc(5 / std::sqrt(2.0));
  CHECK(normal.expected_value() == Approx(1.0 + 0.1 * phi5 / (1 - upper_tail)).epsilon(1e-12));
  // Lognormal given by the mean and sd of R itself (no truncation).
  const PropertyLaw lognormal = law(Distribution::lognormal, 1.0, 0.3, 0.0, inf);
  check_sample(lognormal, 1.0, 0.3, 12);
  CHECK(lognormal.expected_value() == Approx(1.0).epsilon(1e-9));
  CHECK(lognormal.expectation([](double r) { return r * r; }) == Approx(1.0 + 0.09).epsilon(1e-9));  // E[R²] = m² + s²
  // Uniform on [0.5, 1.5]: mean 1, sd 1/sqrt(12).
  PropertyLaw uniform;
  uniform.distribution = Distribution::uniform;
  uniform.min = 0.5;
  uniform.max = 1.5;
  check_sample(uniform, 1.0, 1 / std::sqrt(12.0), 13);
  CHECK(uniform.expectation([](double r) { return r * r * r; }) == Approx((std::pow(1.5, 4) - std::pow(0.5, 4)) / 4).epsilon(1e-12));
}

TEST_CASE("a truncated normal has the moments of the truncated density", "[particles][property_law]") {
  // Mean 1, sd 0.5 on [0.5, 2]: a strong cut on both sides. Moments by Simpson's rule on the density.
  const PropertyLaw p = law(Distribution::normal, 1.0, 0.5, 0.5, 2.0);
  const auto density = [](double x) { return normal_density(x, 1.0, 0.5); };
  const double mass = simpson(density, 0.5, 2.0);
  const double mean = simpson([&](double x) { return x * density(x); }, 0.5, 2.0) / mass;
  const double second = simpson([&](double x) { return x * x * density(x); }, 0.5, 2.0) / mass;
  const double sd = std::sqrt(second - mean * mean);
  CHECK(p.window_probability() == Approx(mass).epsilon(1e-10));
  CHECK(p.expected_value() == Approx(mean).epsilon(1e-10));
  CHECK(mean > 1.05);  // the cut below removes more than the cut above
  check_sample(p, mean, sd, 21);
}

TEST_CASE("E[R^3] by GSL quadrature agrees with a Monte Carlo mean", "[particles][property_law]") {
  // A lognormal cut to [0.5, 2]: the expected particle volume needs E[R³] of the truncated law.
  const PropertyLaw p = law(Distribution::lognormal, 1.0, 0.4, 0.5, 2.0);
  const auto cube = [](double r) { return r * r * r; };
  const double quadrature = p.expectation(cube);
  std::vector<double> r3 = p.draw(samples, 31);
  for (double& r : r3) r = cube(r);
  const Moments m = moments(r3);
  INFO("quadrature " << quadrature << ", Monte Carlo " << m.mean << " ± " << m.mean_error);
  CHECK(std::abs(quadrature - m.mean) < 4 * m.mean_error);
  // Untruncated: E[R³] = exp(3μ + 9σ²/2) exactly.
  const PropertyLaw wide = law(Distribution::lognormal, 1.0, 0.4, 0.0, inf);
  const double s2 = std::log1p(0.16), mu = -s2 / 2;
  CHECK(wide.expectation(cube) == Approx(std::exp(3 * mu + 4.5 * s2)).epsilon(1e-9));
}

TEST_CASE("draws are reproducible from the seed", "[particles][property_law]") {
  const PropertyLaw p = law(Distribution::normal, 1.0, 0.2, 0.1, inf);
  CHECK(p.draw(100, 5) == p.draw(100, 5));
  CHECK(p.draw(100, 5) != p.draw(100, 6));
  CHECK(PropertyLaw::fixed(0.25).draw(3, 1) == std::vector<double>{0.25, 0.25, 0.25});
}

TEST_CASE("bad laws name the entry, the value and what is allowed", "[particles][property_law]") {
  const auto check = [](const PropertyLaw& p, const std::string& key, const std::string& value) {
    INFO(p.describe());
    try {
      p.validate("radius");
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.key() == key);
      CHECK_THAT(e.what(), Contains(" = " + value + ": "));
    }
  };
  check(PropertyLaw::fixed(0), "radius", "0");
  check(PropertyLaw::fixed(-1), "radius", "-1");
  check(PropertyLaw::fixed(std::nan("")), "radius", "nan");
  check(law(Distribution::normal, 1, -0.1, 0.5, inf), "radius.sd", "-0.1");
  check(law(Distribution::normal, 1, 0, 0.5, inf), "radius.sd", "0");
  check(law(Distribution::normal, -1, 0.1, 0.5, inf), "radius.mean", "-1");
  check(law(Distribution::normal, 1, 0.1, 0, inf), "radius.min", "0");  // a normal law needs min > 0
  check(law(Distribution::normal, 1, 0.1, 2, 1.5), "radius.min", "2");
  check(law(Distribution::lognormal, 0, 0.1, 0, inf), "radius.mean", "0");
  check(law(Distribution::lognormal, 1, 0.1, -1, inf), "radius.min", "-1");
  // Windows holding a negligible part of the law: the bound that moved off the bulk is named.
  check(law(Distribution::normal, 1, 0.1, 1.5, inf), "radius.min", "1.5");
  check(law(Distribution::lognormal, 1, 0.1, 0, 0.6), "radius.max", "0.6");
  PropertyLaw uniform;
  uniform.distribution = Distribution::uniform;
  uniform.min = 0;
  uniform.max = 1;
  check(uniform, "radius.min", "0");
  uniform.min = 1;
  uniform.max = inf;
  check(uniform, "radius.max", "inf");
  CHECK_THROWS_AS(distribution_from_name("weibull"), InputError);
  CHECK_NOTHROW(law(Distribution::normal, 1, 0.1, 0.8, 1.2).validate("radius"));
}
