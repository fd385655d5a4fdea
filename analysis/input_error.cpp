#include "analysis/input_error.hpp"

#include <cmath>
#include <sstream>

namespace aggkit {

std::string format_value(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

}  // namespace aggkit
