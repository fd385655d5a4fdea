#include "solvers/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/input_error.hpp"
#include "solvers/low_rank.hpp"

namespace aggkit {

namespace {

using Feature = std::function<double(double)>;

// An exact separable form K_ij = Σ_pq C_pq φ_p(i) φ_q(j) from closed-form features.
std::function<SeparableForm(std::size_t)> exact(std::vector<Feature> features,
                                                std::vector<std::vector<double>> coupling) {
  return [features = std::move(features), coupling = std::move(coupling)](std::size_t N) {
    SeparableForm form;
    form.coupling = coupling;
    for (const auto& phi : features) {
      std::vector<double> values(N);
      for (std::size_t k = 1; k <= N; ++k) values[k - 1] = phi(double(k));
      form.features.push_back(std::move(values));
    }
    return form;
  };
}

double require_finite(const std::string& key, double value, const std::string& allowed) {
  if (!std::isfinite(value)) throw InputError(key, format_value(value), allowed);
  return value;
}

}  // namespace

Kernel::Kernel(std::string name, std::map<std::string, double> parameters, Function f)
    : name_(std::move(name)), parameters_(std::move(parameters)), function_(std::move(f)) {}

Kernel Kernel::constant() {
  Kernel k("constant", {}, [](double, double) { return 1.0; });
  k.exact_form_ = exact({[](double) { return 1.0; }}, {{1.0}});
  return k;
}

Kernel Kernel::sum() {
  Kernel k("sum", {}, [](double i, double j) { return i + j; });
  k.exact_form_ = exact({[](double) { return 1.0; }, [](double s) { return s; }}, {{0.0, 1.0}, {1.0, 0.0}});
  return k;
}

Kernel Kernel::product() {
  Kernel k("product", {}, [](double i, double j) { return i * j; });
  k.exact_form_ = exact({[](double s) { return s; }}, {{1.0}});
  return k;
}

Kernel Kernel::linear(double A, double B) {
  require_finite("kernel.A", A, "a finite number >= 0");
  require_finite("kernel.B", B, "a finite number >= 0");
  if (A < 0) throw InputError("kernel.A", format_value(A), "must be >= 0 (the kernel must stay positive)");
  if (B < 0) throw InputError("kernel.B", format_value(B), "must be >= 0 (the kernel must stay positive)");
  Kernel k("linear", {{"A", A}, {"B", B}}, [A, B](double i, double j) { return 1.0 + A * (i + j) + B * i * j; });
  k.exact_form_ = exact({[](double) { return 1.0; }, [](double s) { return s; }}, {{1.0, A}, {A, B}});
  return k;
}

Kernel Kernel::generalized_product(double mu) {
  require_finite("kernel.mu", mu, "a finite exponent");
  if (mu < 0.0 || mu > 1.0)
    throw InputError("kernel.mu", format_value(mu), "must lie in [0, 1] (mu > 1/2 gels at finite time)");
  Kernel k("genproduct", {{"mu", mu}}, [mu](double i, double j) { return std::pow(i * j, mu); });
  k.exact_form_ = exact({[mu](double s) { return std::pow(s, mu); }}, {{1.0}});
  return k;
}

Kernel Kernel::ballistic() {
  // Free-molecular ballistic kernel for compact clusters: cross-section ∝ (i^{1/3}+j^{1/3})^2,
  // relative speed ∝ sqrt(1/i + 1/j) [Kalinov2022, eq. 2].
  return Kernel("ballistic", {}, [](double i, double j) {
    const double r = std::cbrt(i) + std::cbrt(j);
    return r * r * std::sqrt(1.0 / i + 1.0 / j);
  });
}

Kernel Kernel::ballistic2d() {
  // No exact factorisation (the square root couples i and j): approximated like the 3-D ballistic kernel.
  return Kernel("ballistic2d", {}, [](double i, double j) {
    return (std::sqrt(i) + std::sqrt(j)) * std::sqrt(1.0 / i + 1.0 / j);
  });
}

Kernel Kernel::brownian(double a) {
  require_finite("kernel.a", a, "a finite exponent in [0, 1]");
  if (a < 0.0 || a > 1.0) throw InputError("kernel.a", format_value(a), "must lie in [0, 1]");
  // K_ij = (i/j)^a + (j/i)^a = i^a j^{-a} + i^{-a} j^a: rank 2 (a = 0 gives K = 2).
  Kernel k("brownian", {{"a", a}}, [a](double i, double j) { return std::pow(i / j, a) + std::pow(j / i, a); });
  k.exact_form_ = exact({[a](double s) { return std::pow(s, a); }, [a](double s) { return std::pow(s, -a); }},
                        {{0.0, 1.0}, {1.0, 0.0}});
  return k;
}

Kernel Kernel::user(std::string name, Function f) { return Kernel(std::move(name), {}, std::move(f)); }

std::vector<std::string> Kernel::names() {
  return {"constant", "sum", "product", "linear", "genproduct", "ballistic", "brownian", "ballistic2d"};
}

Kernel Kernel::from_name(const std::string& name, const std::map<std::string, double>& parameters) {
  struct Entry {
    std::vector<std::string> keys;
    std::function<Kernel(const std::map<std::string, double>&)> make;
  };
  auto get = [](const std::map<std::string, double>& p, const std::string& key, double fallback) {
    auto it = p.find(key);
    return it == p.end() ? fallback : it->second;
  };
  const std::map<std::string, Entry> table = {
      {"constant", {{}, [](auto&) { return constant(); }}},
      {"sum", {{}, [](auto&) { return sum(); }}},
      {"product", {{}, [](auto&) { return product(); }}},
      {"linear", {{"A", "B"}, [&](auto& p) { return linear(get(p, "A", 0.0), get(p, "B", 0.0)); }}},
      {"genproduct", {{"mu"}, [&](auto& p) {
         if (!p.count("mu")) throw InputError("kernel.mu", "(missing)", "genproduct needs mu in [0, 1]");
         return generalized_product(p.at("mu"));
       }}},
      {"ballistic", {{}, [](auto&) { return ballistic(); }}},
      {"ballistic2d", {{}, [](auto&) { return ballistic2d(); }}},
      {"brownian", {{"a"}, [&](auto& p) {
         if (!p.count("a")) throw InputError("kernel.a", "(missing)", "brownian needs a in [0, 1]");
         return brownian(p.at("a"));
       }}},
  };
  auto it = table.find(name);
  if (it == table.end()) {
    std::string allowed = "one of";
    for (const auto& n : names()) allowed += " " + n;
    throw InputError("kernel.name", "\"" + name + "\"", allowed);
  }
  for (const auto& [key, value] : parameters) {
    if (std::find(it->second.keys.begin(), it->second.keys.end(), key) == it->second.keys.end()) {
      std::string allowed = it->second.keys.empty() ? "kernel '" + name + "' takes no parameters"
                                                     : "kernel '" + name + "' takes:";
      for (const auto& k : it->second.keys) allowed += " " + k;
      throw InputError("kernel." + key, format_value(value), allowed);
    }
  }
  return it->second.make(parameters);
}

std::string Kernel::describe() const {
  std::ostringstream out;
  out << name_;
  if (!parameters_.empty()) {
    out << "(";
    bool first = true;
    for (const auto& [k, v] : parameters_) out << (first ? "" : ", ") << k << "=" << v, first = false;
    out << ")";
  }
  return out.str();
}

SeparableForm Kernel::separable_form(std::size_t N, double tolerance) const {
  if (exact_form_) return exact_form_(N);
  return cross_approximation([this](std::size_t i, std::size_t j) { return (*this)(i, j); }, N, tolerance);
}

}  // namespace aggkit
