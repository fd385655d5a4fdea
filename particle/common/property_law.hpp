#pragma once
// The law of a per-particle property (a radius or a mass): one value shared by every particle, or a
// distribution drawn independently for each particle of each realization:
//   normal     mean and standard deviation of the property itself, truncated to [min, max] (min > 0 required:
//              the property is positive);
//   lognormal  mean m and standard deviation s of the property X itself (not of ln X): ln X is normal with
//              σ² = ln(1 + s²/m²) and μ = ln m − σ²/2; optionally truncated to [min, max];
//   uniform    on [min, max].
// Truncation is by rejection (draw from the untruncated law until the value falls in the window), so a
// window must hold a sizeable part of the law (min_window_probability); mean and sd stay those of the
// untruncated law, and expected_value() gives the mean of the truncated one.
// Expectations E[g(X)] of the (truncated) law are computed by GSL adaptive quadrature.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace aggkit {

enum class Distribution { fixed, normal, lognormal, uniform };

// "normal" | "lognormal" | "uniform"; InputError (key "distribution") otherwise.
Distribution distribution_from_name(std::string_view name);
std::string to_string(Distribution distribution);

// The smallest probability a truncation window [min, max] may hold: rejection then needs at most about
// 1/min_window_probability draws per particle.
inline constexpr double min_window_probability = 1e-3;

struct PropertyLaw {
  Distribution distribution = Distribution::fixed;
  double value = 0;  // fixed: the value of every particle
  double mean = 0;   // normal, lognormal: mean of the untruncated law
  double sd = 0;     // normal, lognormal: standard deviation of the untruncated law
  double min = 0;    // normal, lognormal: truncation window (lognormal: 0 = none below); uniform: the range
  double max = std::numeric_limits<double>::infinity();

  static PropertyLaw fixed(double value);
  bool is_fixed() const { return distribution == Distribution::fixed; }

  // Throws InputError naming `name` ("radius", "mass") or one of its entries ("radius.sd", "radius.min"),
  // the value and what is allowed: fixed value, mean, sd and (normal, uniform) min finite and > 0,
  // min < max, and a window holding at least min_window_probability of the untruncated law.
  void validate(const std::string& name) const;

  // Probability of [min, max] under the untruncated law (1 for fixed and uniform).
  double window_probability() const;
  // E[g(X)] under the truncated law (g(value) for fixed); GSL quadrature to a relative 1e-10. Thread-safe;
  // g must not itself call expectation (the quadratures are serialised).
  double expectation(const std::function<double(double)>& g) const;
  double expected_value() const;  // E[X]
  double smallest() const;        // the smallest value a draw can take (min, or value)
  double largest() const;         // the largest (max, +inf for an untruncated tail, or value)

  // `count` independent draws from a stream seeded with `seed` (std::mt19937_64 and the <random> laws).
  std::vector<double> draw(std::size_t count, std::uint64_t seed) const;
  std::string describe() const;  // "0.5", "normal(mean 1, sd 0.1) on [0.5, inf)"
};

}  // namespace aggkit
