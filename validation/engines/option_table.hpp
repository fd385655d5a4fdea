#pragma once
// Engine options declared once: each engine kind has a table of its keys (type, default, allowed range,
// one line of documentation). The table drives the reading of a scene's [[engine]] table (unknown keys,
// types and ranges are refused with the dotted key `engine[i].key`, the value and what is allowed), the
// engines section of `aggkit run --help`, and the keyword arguments of the Python module.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace aggkit {

struct OptionSpec {
  enum class Type { boolean, integer, number, word, custom };
  std::string key;
  Type type = Type::number;
  std::string default_text;  // as --help shows it ("1e-06", "rtol/100", "off")
  std::string doc;           // one line
  // integer and number: the allowed range; `above` makes the lower bound exclusive (number only).
  double minimum = -std::numeric_limits<double>::infinity();
  double maximum = std::numeric_limits<double>::infinity();
  bool above = false;
  std::vector<std::string> words;  // word: the allowed values
  std::string forms;               // custom: what is allowed (the engine reads the value itself)

  std::string allowed() const;     // "a number > 0", "an integer in 1..10000", "one of a, b"
};
using OptionTable = std::vector<OptionSpec>;

// Shorthands for table rows.
OptionSpec flag_option(std::string key, bool fallback, std::string doc);
OptionSpec integer_option(std::string key, std::string fallback, std::string doc, double minimum,
                          double maximum = 9.007199254740992e15);
OptionSpec number_option(std::string key, std::string fallback, std::string doc, double minimum, double maximum,
                         bool above = false);
OptionSpec word_option(std::string key, std::string fallback, std::string doc, std::vector<std::string> words);
OptionSpec custom_option(std::string key, std::string fallback, std::string doc, std::string forms);

// The options given to one engine, checked against its table. Values are JSON (a scene's TOML table, or
// the keyword arguments of a Python call).
class EngineOptions {
 public:
  // Throws InputError for a key not in `table`, a value of the wrong type or out of range; `path` names
  // the table in messages ("engine[1]").
  EngineOptions(const OptionTable& table, const nlohmann::json& given, std::string path);

  bool has(std::string_view key) const { return given_.contains(std::string(key)); }
  bool boolean(std::string_view key, bool fallback) const;
  std::int64_t integer(std::string_view key, std::int64_t fallback) const;
  double number(std::string_view key, double fallback) const;
  std::string word(std::string_view key, const std::string& fallback) const;
  const nlohmann::json& value(std::string_view key) const;  // a custom option as given

  std::string key(std::string_view name) const { return path_ + "." + std::string(name); }
  const std::string& path() const { return path_; }
  // InputError for option `name` with its value as given.
  [[noreturn]] void fail(std::string_view name, const std::string& allowed) const;

 private:
  const OptionSpec& spec(std::string_view key) const;
  const OptionTable* table_;
  nlohmann::json given_;
  std::string path_;
};

// The text of a JSON value as a scene writes it (strings quoted, numbers shortest, nan as nan).
std::string option_text(const nlohmann::json& value);

}  // namespace aggkit
