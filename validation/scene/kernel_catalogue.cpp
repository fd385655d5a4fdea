#include "validation/scene/kernel_catalogue.hpp"

#include <cstdio>

#include "solvers/exact_solutions.hpp"
#include "solvers/kernels.hpp"

namespace aggkit {

std::vector<std::string> KernelEntry::parameter_names() const {
  std::vector<std::string> names;
  for (const auto& p : parameters) names.push_back(p.name);
  return names;
}

// Formulas as in the README's tour; ballistic kernel from [Kalinov2022], ballistic2d from [Carnevale1990].
const std::vector<KernelEntry>& kernel_catalogue() {
  static const std::vector<KernelEntry> catalogue{
      {"constant", "K_ij = 1", {}},
      {"sum", "K_ij = i + j", {}},
      {"product", "K_ij = i j  (gels at t = 1)", {}},
      {"linear", "K_ij = 1 + A (i + j) + B i j", {{"A", "A >= 0"}, {"B", "B >= 0"}}},
      {"genproduct", "K_ij = (i j)^mu", {{"mu", "0 <= mu <= 1"}}},
      {"ballistic", "K_ij = (i^(1/3) + j^(1/3))^2 sqrt(1/i + 1/j)", {}},
      {"brownian", "K_ij = (i/j)^a + (j/i)^a", {{"a", "0 <= a <= 1"}}},
      {"ballistic2d", "K_ij = (i^(1/2) + j^(1/2)) sqrt(1/i + 1/j)  (2-D discs)", {}},
  };
  return catalogue;
}

const KernelEntry* find_kernel_entry(std::string_view name) {
  for (const auto& entry : kernel_catalogue())
    if (entry.name == name) return &entry;
  return nullptr;
}

void print_kernel_catalogue(std::ostream& out) {
  out << "kernels (scene: [model] kernel = { name = \"...\", <parameter> = <value>, ... })\n\n";
  for (const std::string& name : Kernel::names()) {
    const KernelEntry* entry = find_kernel_entry(name);
    std::string parameters;
    for (const auto& p : entry ? entry->parameters : std::vector<KernelParameter>{})
      parameters += (parameters.empty() ? "" : ", ") + p.allowed;
    char line[512];
    std::snprintf(line, sizeof line, "  %-11s %-48s %s\n", name.c_str(), entry ? entry->formula.c_str() : "",
                  parameters.empty() ? "no parameters" : parameters.c_str());
    out << line;
  }
  out << "\nthe exact engine covers:";
  for (const std::string& name : Kernel::names())
    if (has_exact_solution(name)) out << " " << name;
  out << " (lambda = 0, unit monodisperse start)\n";
}

}  // namespace aggkit
