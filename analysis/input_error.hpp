#pragma once
// Bad user input: every message names the key, the value and what is allowed.
#include <stdexcept>
#include <string>

namespace aggkit {

class InputError : public std::invalid_argument {
 public:
  InputError(const std::string& key, const std::string& value, const std::string& allowed)
      : std::invalid_argument(key + " = " + value + ": " + allowed), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Formats a double for messages so that NaN/inf/negative values read clearly.
std::string format_value(double value);

}  // namespace aggkit
