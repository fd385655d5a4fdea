#pragma once
// The command-line tests build shell commands for std::system: one word in single quotes, with embedded
// single quotes closed, escaped and reopened ('\''), so paths and scene text pass through unchanged.
#include <string>

namespace aggkit::testing {

inline std::string quoted(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace aggkit::testing
