#include "solvers/model.hpp"

#include <cmath>

#include "analysis/input_error.hpp"

namespace aggkit {

Truncation truncation_from_name(const std::string& name) {
  if (name == "drop") return Truncation::drop;
  if (name == "cutoff") return Truncation::cutoff;
  throw InputError("truncation", "\"" + name + "\"", "one of drop, cutoff");
}

std::string to_string(Truncation t) { return t == Truncation::drop ? "drop" : "cutoff"; }

void AggregationModel::validate(double t_end) const {
  if (size < 2) throw InputError("size", std::to_string(size), "the truncation N must be >= 2");
  if (initial.size() > size)
    throw InputError("initial.n", std::to_string(initial.size()) + " entries",
                     "at most model.size = " + std::to_string(size) + " entries");
  double mass = 0.0;
  for (std::size_t k = 0; k < initial.size(); ++k) {
    if (!std::isfinite(initial[k]) || initial[k] < 0.0)
      throw InputError("initial.n[" + std::to_string(k) + "]", format_value(initial[k]),
                       "densities must be finite and >= 0");
    mass += double(k + 1) * initial[k];
  }
  if (!(mass > 0.0)) throw InputError("initial", "zero mass", "at least one density must be > 0");
  lambda.validate(t_end);
  grid.validate();
}

std::vector<double> monodisperse(std::size_t N, double density) {
  std::vector<double> n(N, 0.0);
  if (N > 0) n[0] = density;
  return n;
}

}  // namespace aggkit
