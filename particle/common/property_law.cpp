#include "particle/common/property_law.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// ln X ~ N(μ, σ²) with E[X] = m and sd[X] = s: E[X] = e^{μ+σ²/2}, Var[X] = (e^{σ²} − 1) e^{2μ+σ²}, so
// σ² = ln(1 + s²/m²) and μ = ln m − σ²/2.
struct LogNormal {
  double mu, sigma;
};
LogNormal log_normal(double mean, double sd) {
  const double variance = std::log1p((sd / mean) * (sd / mean));
  return {std::log(mean) - variance / 2, std::sqrt(variance)};
}

// GSL's default error handler aborts the process; within this scope errors come back as status codes. The
// handler is process-wide: the lock keeps concurrent quadratures (realizations started in threads) from
// interleaving their save and restore.
class GslStatusReturned {
 public:
  GslStatusReturned() : lock_(mutex()), previous_(gsl_set_error_handler_off()) {}
  ~GslStatusReturned() { gsl_set_error_handler(previous_); }
  GslStatusReturned(const GslStatusReturned&) = delete;
  GslStatusReturned& operator=(const GslStatusReturned&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  gsl_error_handler_t* previous_;
};

double call(double x, void* f) { return (*static_cast<const std::function<double(double)>*>(f))(x); }

// ∫_a^b f (a, b finite) by GSL's adaptive Gauss–Kronrod quadrature with extrapolation (QAGS).
double integrate(const std::function<double(double)>& f, double a, double b) {
  constexpr std::size_t limit = 1000;
  const GslStatusReturned scope;
  const std::unique_ptr<gsl_integration_workspace, decltype(&gsl_integration_workspace_free)> workspace(
      gsl_integration_workspace_alloc(limit), &gsl_integration_workspace_free);
  if (!workspace) throw std::bad_alloc();
  gsl_function function{&call, const_cast<std::function<double(double)>*>(&f)};
  double result = 0, error = 0;
  const int status = gsl_integration_qags(&function, a, b, /*epsabs=*/0, /*epsrel=*/1e-10, limit, workspace.get(), &result, &error);
  // GSL_EROUND: round-off stopped the refinement short of 1e-10; the estimate is still good to ~1e-12.
  if (status != GSL_SUCCESS && status != GSL_EROUND)
    throw std::runtime_error(std::string("quadrature of a property law failed: ") + gsl_strerror(status));
  return result;
}

// Beyond |z| = 40 the standard normal density (< 1e-347) is zero in double precision: the integrals over z
// are taken on [-40, 40] and finite.
constexpr double z_reach = 40;

// Φ(b) − Φ(a) for the standard normal, taken from the nearer tail so that far windows keep their digits.
double normal_probability(double a, double b) {
  const auto lower = [](double z) { return std::isinf(z) ? (z > 0 ? 1.0 : 0.0) : gsl_cdf_ugaussian_P(z); };
  const auto upper = [](double z) { return std::isinf(z) ? (z > 0 ? 0.0 : 1.0) : gsl_cdf_ugaussian_Q(z); };
  return a > 0 ? upper(a) - upper(b) : lower(b) - lower(a);
}

// The truncation window in standard-normal coordinates z, and the map z -> x, for normal and lognormal laws.
struct StandardForm {
  double low, high;
  std::function<double(double)> x;
};
StandardForm standard_form(const PropertyLaw& law) {
  if (law.distribution == Distribution::normal) {
    const double m = law.mean, s = law.sd;
    return {(law.min - m) / s, (law.max - m) / s, [m, s](double z) { return m + s * z; }};
  }
  const LogNormal p = log_normal(law.mean, law.sd);
  const double low = law.min > 0 ? (std::log(law.min) - p.mu) / p.sigma : -infinity;
  const double high = std::isinf(law.max) ? infinity : (std::log(law.max) - p.mu) / p.sigma;
  return {low, high, [p](double z) { return std::exp(p.mu + p.sigma * z); }};
}

double standard_normal_density(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2 * std::numbers::pi); }

[[noreturn]] void fail(const std::string& key, double value, const std::string& allowed) {
  throw InputError(key, format_value(value), allowed);
}

void require_positive(const std::string& key, double value, const std::string& what) {
  if (!(value > 0) || !std::isfinite(value)) fail(key, value, "a finite " + what + " > 0");
}

}  // namespace

Distribution distribution_from_name(std::string_view name) {
  if (name == "normal") return Distribution::normal;
  if (name == "lognormal") return Distribution::lognormal;
  if (name == "uniform") return Distribution::uniform;
  throw InputError("distribution", "\"" + std::string(name) + "\"", "\"normal\", \"lognormal\" or \"uniform\"");
}

std::string to_string(Distribution distribution) {
  switch (distribution) {
    case Distribution::fixed: return "fixed";
    case Distribution::normal: return "normal";
    case Distribution::lognormal: return "lognormal";
    case Distribution::uniform: return "uniform";
  }
  return "unknown";
}

PropertyLaw PropertyLaw::fixed(double value) {
  PropertyLaw law;
  law.value = value;
  return law;
}

void PropertyLaw::validate(const std::string& name) const {
  // Sizes and masses enter as powers (R³, m R²): parameters beyond 1e100 overflow them and defeat the
  // quadratures of the law's moments.
  if (distribution != Distribution::fixed)
    for (const auto& [field, x] : {std::pair<const char*, double>{"mean", mean}, {"sd", sd}, {"min", min}, {"max", max}})
      if (std::isfinite(x) && std::abs(x) > 1e100)
        fail(name + "." + field, x, "a value of magnitude at most 1e100 (powers of it must stay finite)");
  switch (distribution) {
    case Distribution::fixed:
      if (!(value > 0) || !std::isfinite(value))
        fail(name, value, "a finite number > 0, or a table { distribution = \"normal\" | \"lognormal\" | \"uniform\", ... }");
      // Sizes and masses enter as powers and products (R³, m*, k_n = m*(π² + ln²e)/t_c²): keep them where
      // those stay normal doubles.
      if (!(value >= 1e-100 && value <= 1e100)) fail(name, value, "a number in [1e-100, 1e100] (powers of it must stay finite)");
      return;
    case Distribution::normal:
    case Distribution::lognormal:
      require_positive(name + ".mean", mean, "mean");
      if (!(sd > 0) || !std::isfinite(sd))
        fail(name + ".sd", sd, "a finite standard deviation > 0 (for equal values give one number instead of a table)");
      if (distribution == Distribution::lognormal && !(sd <= 100 * mean))
        fail(name + ".sd", sd, "at most 100 times the mean for a lognormal law (a wider one spans tens of decades of sizes, "
                               "beyond what its moments can be integrated to)");
      if (distribution == Distribution::normal)
        require_positive(name + ".min", min, "lower bound (a normal law is truncated to [min, max], and values must be positive)");
      else if (!(min >= 0) || !std::isfinite(min))
        fail(name + ".min", min, "a finite lower bound >= 0");
      break;
    case Distribution::uniform:
      require_positive(name + ".min", min, "lower bound");
      if (!std::isfinite(max)) fail(name + ".max", max, "a finite upper bound");
      break;
  }
  if (!(max > min)) fail(name + ".min", min, "a lower bound below max = " + format_value(max));
  const double probability = window_probability();
  if (!(probability >= min_window_probability)) {
    // Name the bound that moved the window off the bulk of the law.
    const double centre = distribution == Distribution::normal ? mean : std::exp(log_normal(mean, sd).mu);
    const bool above = min > centre;
    std::ostringstream allowed;
    allowed << "a truncation window [min, max] holding at least " << min_window_probability
            << " of the law (values are drawn by rejection); [" << format_value(min) << ", " << format_value(max)
            << (std::isinf(max) ? ")" : "]") << " holds " << probability;
    fail(name + (above ? ".min" : ".max"), above ? min : max, allowed.str());
  }
}

double PropertyLaw::window_probability() const {
  if (distribution == Distribution::fixed || distribution == Distribution::uniform) return 1.0;
  const StandardForm form = standard_form(*this);
  return normal_probability(form.low, form.high);
}

double PropertyLaw::expectation(const std::function<double(double)>& g) const {
  switch (distribution) {
    case Distribution::fixed: return g(value);
    case Distribution::uniform: return integrate(g, min, max) / (max - min);
    case Distribution::normal:
    case Distribution::lognormal: {
      // E[g(X) | min <= X <= max] = ∫_{z_lo}^{z_hi} g(x(z)) φ(z) dz / (Φ(z_hi) − Φ(z_lo)).
      const StandardForm form = standard_form(*this);
      const auto integrand = [&](double z) {
        const double density = standard_normal_density(z);
        return density == 0 ? 0.0 : g(form.x(z)) * density;
      };
      const double low = std::max(form.low, -z_reach), high = std::min(form.high, z_reach);
      return integrate(integrand, low, high) / normal_probability(form.low, form.high);
    }
  }
  return g(value);
}

double PropertyLaw::expected_value() const {
  if (is_fixed()) return value;
  return expectation([](double x) { return x; });
}

double PropertyLaw::smallest() const { return is_fixed() ? value : min; }

double PropertyLaw::largest() const { return is_fixed() ? value : max; }

std::vector<double> PropertyLaw::draw(std::size_t count, std::uint64_t seed) const {
  std::vector<double> values(count, value);
  if (is_fixed()) return values;
  std::mt19937_64 rng(seed);
  const auto truncated = [&](auto law) {
    for (double& x : values) do x = law(rng);
      while (!(x >= min && x <= max));
  };
  switch (distribution) {
    case Distribution::fixed: break;
    case Distribution::normal: truncated(std::normal_distribution<double>(mean, sd)); break;
    case Distribution::lognormal: {
      const LogNormal p = log_normal(mean, sd);
      truncated(std::lognormal_distribution<double>(p.mu, p.sigma));
      break;
    }
    case Distribution::uniform: {
      std::uniform_real_distribution<double> law(min, max);
      for (double& x : values) x = law(rng);
      break;
    }
  }
  return values;
}

std::string PropertyLaw::describe() const {
  if (is_fixed()) return format_value(value);
  std::string window = "[";
  window += format_value(min) + ", " + format_value(max) + (std::isinf(max) ? ")" : "]");
  if (distribution == Distribution::uniform) return "uniform on " + window;
  std::string text = to_string(distribution) + "(mean " + format_value(mean) + ", sd " + format_value(sd) + ")";
  if (distribution == Distribution::normal || min > 0 || !std::isinf(max)) text += " on " + window;
  return text;
}

}  // namespace aggkit
