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
std::function<SeparableForm(std::size_t)> exact(std::shared_ptr<const Kernel::Factors> factors) {
  return [factors = std::move(factors)](std::size_t N) {
    SeparableForm form;
    form.coupling = factors->coupling;
    for (const auto& phi : factors->features) {
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

void Kernel::set_exact(std::vector<Feature> features, std::vector<std::vector<double>> coupling) {
  exact_factors_ = std::make_shared<const Factors>(Factors{std::move(features), std::move(coupling)});
  exact_form_ = exact(exact_factors_);
}

Kernel Kernel::constant() {
  Kernel k("constant", {}, [](double, double) { return 1.0; });
  k.set_exact({[](double) { return 1.0; }}, {{1.0}});
  return k;
}

Kernel Kernel::sum() {
  Kernel k("sum", {}, [](double i, double j) { return i + j; });
  k.set_exact({[](double) { return 1.0; }, [](double s) { return s; }}, {{0.0, 1.0}, {1.0, 0.0}});
  return k;
}

Kernel Kernel::product() {
  Kernel k("product", {}, [](double i, double j) { return i * j; });
  k.set_exact({[](double s) { return s; }}, {{1.0}});
  return k;
}

Kernel Kernel::linear(double A, double B) {
  require_finite("kernel.A", A, "a finite number >= 0");
  require_finite("kernel.B", B, "a finite number >= 0");
  if (A < 0) throw InputError("kernel.A", format_value(A), "must be >= 0 (the kernel must stay positive)");
  if (B < 0) throw InputError("kernel.B", format_value(B), "must be >= 0 (the kernel must stay positive)");
  Kernel k("linear", {{"A", A}, {"B", B}}, [A, B](double i, double j) { return 1.0 + A * (i + j) + B * i * j; });
  k.set_exact({[](double) { return 1.0; }, [](double s) { return s; }}, {{1.0, A}, {A, B}});
  return k;
}

Kernel Kernel::generalized_product(double mu) {
  require_finite("kernel.mu", mu, "a finite exponent");
  if (mu < 0.0 || mu > 1.0)
    throw InputError("kernel.mu", format_value(mu), "must lie in [0, 1] (mu > 1/2 gels at finite time)");
  Kernel k("genproduct", {{"mu", mu}}, [mu](double i, double j) { return std::pow(i * j, mu); });
  k.set_exact({[mu](double s) { return std::pow(s, mu); }}, {{1.0}});
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
  k.set_exact({[a](double s) { return std::pow(s, a); }, [a](double s) { return std::pow(s, -a); }},
                        {{0.0, 1.0}, {1.0, 0.0}});
  return k;
}

Kernel Kernel::user(std::string name, Function f) { return Kernel(std::move(name), {}, std::move(f)); }

// Formulas as in the README's tour; ballistic kernel from [Kalinov2022], ballistic2d from [Carnevale1990].
const std::vector<KernelEntry>& kernel_registry() {
  using P = std::map<std::string, double>;
  static const std::vector<KernelEntry> registry{
      {"constant", "K_ij = 1", {}, [](const P&) { return Kernel::constant(); }},
      {"sum", "K_ij = i + j", {}, [](const P&) { return Kernel::sum(); }},
      {"product", "K_ij = i j  (gels at t = 1)", {}, [](const P&) { return Kernel::product(); }},
      {"linear", "K_ij = 1 + A (i + j) + B i j", {{"A", "A >= 0", 0.0}, {"B", "B >= 0", 0.0}},
       [](const P& p) { return Kernel::linear(p.at("A"), p.at("B")); }},
      {"genproduct", "K_ij = (i j)^mu", {{"mu", "0 <= mu <= 1", std::nullopt}},
       [](const P& p) { return Kernel::generalized_product(p.at("mu")); }},
      {"ballistic", "K_ij = (i^(1/3) + j^(1/3))^2 sqrt(1/i + 1/j)", {}, [](const P&) { return Kernel::ballistic(); }},
      {"brownian", "K_ij = (i/j)^a + (j/i)^a", {{"a", "0 <= a <= 1", std::nullopt}},
       [](const P& p) { return Kernel::brownian(p.at("a")); }},
      {"ballistic2d", "K_ij = (i^(1/2) + j^(1/2)) sqrt(1/i + 1/j)  (2-D discs)", {},
       [](const P&) { return Kernel::ballistic2d(); }},
  };
  return registry;
}

const KernelEntry* find_kernel_entry(std::string_view name) {
  for (const KernelEntry& entry : kernel_registry())
    if (entry.name == name) return &entry;
  return nullptr;
}

std::vector<std::string> KernelEntry::parameter_names() const {
  std::vector<std::string> names;
  for (const KernelParameter& p : parameters) names.push_back(p.name);
  return names;
}

std::vector<std::string> Kernel::names() {
  std::vector<std::string> names;
  for (const KernelEntry& entry : kernel_registry()) names.push_back(entry.name);
  return names;
}

Kernel Kernel::from_name(const std::string& name, const std::map<std::string, double>& parameters) {
  const KernelEntry* entry = find_kernel_entry(name);
  if (!entry) {
    std::string allowed = "one of";
    for (const auto& n : names()) allowed += " " + n;
    throw InputError("kernel.name", "\"" + name + "\"", allowed);
  }
  const std::vector<std::string> keys = entry->parameter_names();
  for (const auto& [key, value] : parameters) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      std::string allowed = keys.empty() ? "kernel '" + name + "' takes no parameters" : "kernel '" + name + "' takes:";
      for (const auto& k : keys) allowed += " " + k;
      throw InputError("kernel." + key, format_value(value), allowed);
    }
  }
  std::map<std::string, double> values = parameters;
  for (const KernelParameter& p : entry->parameters)
    if (!values.count(p.name)) {
      if (!p.fallback) throw InputError("kernel." + p.name, "(missing)", name + " needs " + p.allowed);
      values[p.name] = *p.fallback;
    }
  return entry->make(values);
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
