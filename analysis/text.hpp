#pragma once
// Small text helpers for messages, shared by every layer (validation/io/text.hpp adds the output forms).
#include <string>
#include <string_view>
#include <vector>

namespace aggkit {

// The shortest text that reads back to `value` ("0.95", "1e-08", "nan", "-inf").
std::string shortest_text(double value);
// A TOML float as it reads back as a float: shortest_text, with ".0" added to an integral value ("200.0").
std::string float_text(double value);
// `text` with control characters written as \uXXXX escapes, safe to print on a terminal.
std::string printable_text(const std::string& text);
// "a, b, c".
std::string join(const std::vector<std::string>& words, std::string_view separator = ", ");

}  // namespace aggkit
