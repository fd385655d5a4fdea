#include "validation/io/text.hpp"

#include <cstdio>

namespace aggkit {

std::string full_precision_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

}  // namespace aggkit
