#include "validation/scene/kernel_catalogue.hpp"

#include <cstdio>
#include <string>

#include "solvers/exact_solutions.hpp"
#include "solvers/kernels.hpp"

namespace aggkit {

void print_kernel_catalogue(std::ostream& out) {
  out << "kernels (scene: [model] kernel = { name = \"...\", <parameter> = <value>, ... })\n\n";
  for (const KernelEntry& entry : kernel_registry()) {
    std::string parameters;
    for (const KernelParameter& p : entry.parameters)
      parameters += (parameters.empty() ? "" : ", ") + p.allowed + (p.fallback ? "" : " (required)");
    char line[512];
    std::snprintf(line, sizeof line, "  %-11s %-48s %s\n", entry.name.c_str(), entry.formula.c_str(),
                  parameters.empty() ? "no parameters" : parameters.c_str());
    out << line;
  }
  out << "\nthe exact engine covers:";
  for (const KernelEntry& entry : kernel_registry())
    if (has_exact_solution(entry.name)) out << " " << entry.name;
  out << " (lambda = 0, unit monodisperse start)\n";
}

}  // namespace aggkit
