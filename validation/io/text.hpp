#pragma once
// Small text helpers shared by the scene parser, the reports and the messages: those of analysis/text.hpp
// and the full-precision form of the CSV outputs.
#include <string>

#include "analysis/text.hpp"

namespace aggkit {

// "%.17g": full precision for the CSV outputs.
std::string full_precision_text(double value);

}  // namespace aggkit
