#pragma once
// What a scene (and `aggkit kernels`) can say about each kernel: its formula and parameters.
// Kernel::from_name (solvers/kernels.hpp) is the authority on values; this catalogue documents them and
// lets the scene parser reject unknown parameter keys. A test checks it lists exactly Kernel::names().
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace aggkit {

struct KernelParameter {
  std::string name;
  std::string allowed;  // e.g. "0 <= a <= 1"
};

struct KernelEntry {
  std::string name;
  std::string formula;
  std::vector<KernelParameter> parameters;
  std::vector<std::string> parameter_names() const;
};

const std::vector<KernelEntry>& kernel_catalogue();
const KernelEntry* find_kernel_entry(std::string_view name);  // nullptr if not catalogued

// The table printed by `aggkit kernels`: every kernel of Kernel::names(), its formula, parameters and
// whether the exact engine covers it.
void print_kernel_catalogue(std::ostream& out);

}  // namespace aggkit
