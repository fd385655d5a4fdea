#pragma once
// Small text helpers shared by the scene parser, the reports and the messages.
#include <string>
#include <string_view>
#include <vector>

namespace aggkit {

// The shortest text that reads back to `value` ("0.95", "1e-08", "nan", "-inf").
std::string shortest_text(double value);
// "%.17g": full precision for the CSV outputs.
std::string full_precision_text(double value);
// "a, b, c".
std::string join(const std::vector<std::string>& words, std::string_view separator = ", ");

}  // namespace aggkit
