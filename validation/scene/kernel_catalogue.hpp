#pragma once
// `aggkit kernels`: the kernel registry (solvers/kernels.hpp: names, formulas, parameters) as a table, with
// the kernels the exact engine covers.
#include <ostream>

namespace aggkit {

void print_kernel_catalogue(std::ostream& out);

}  // namespace aggkit
