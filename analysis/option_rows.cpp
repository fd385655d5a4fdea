#include "analysis/option_rows.hpp"

#include <algorithm>
#include <cstdio>

#include "analysis/text.hpp"

namespace aggkit {

namespace {

std::string integer_text(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.0f", x);
  return buffer;
}

}  // namespace

std::string OptionSpec::allowed() const {
  switch (type) {
    case Type::boolean: return "true or false";
    case Type::word: return "one of " + join(words);
    case Type::custom: return forms;
    case Type::table: {
      std::vector<std::string> keys;
      for (const OptionSpec& row : rows)
        keys.push_back(row.key + " = " + row.allowed() +
                       (row.fallback.is_null() && row.default_note.empty() ? " (required)" : " (default " + row.default_text() + ")"));
      return "a table { " + join(keys) + " }";
    }
    case Type::integer:
      if (std::isinf(range.maximum) || range.maximum >= 9e15) return "an integer >= " + integer_text(range.minimum);
      return "an integer in " + integer_text(range.minimum) + ".." + integer_text(range.maximum);
    case Type::number: {
      const bool low = std::isfinite(range.minimum), high = std::isfinite(range.maximum);
      if (low && high)
        return "a number in " + std::string(range.above ? "(" : "[") + shortest_text(range.minimum) + ", " +
               shortest_text(range.maximum) + (range.below ? ")" : "]");
      if (low) return "a finite number " + std::string(range.above ? "> " : ">= ") + shortest_text(range.minimum);
      if (high) return "a finite number " + std::string(range.below ? "< " : "<= ") + shortest_text(range.maximum);
      return "a finite number";
    }
  }
  return "";
}

std::string OptionSpec::default_text() const {
  if (!default_note.empty()) return default_note;
  if (fallback.is_null()) return "none";
  if (fallback.is_number_float()) return shortest_text(fallback.get<double>());
  if (type == Type::word) return fallback.get<std::string>();
  return option_text(fallback);
}

const OptionSpec* find_option(const OptionTable& table, std::string_view key) {
  for (const OptionSpec& s : table)
    if (s.key == key) return &s;
  return nullptr;
}

std::string option_text(const nlohmann::json& value) {
  if (value.is_number_float()) return float_text(value.get<double>());
  if (value.is_string()) {
    std::string text(1, '"');
    text += printable_text(value.get<std::string>());
    return text += '"';
  }
  if (value.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < value.size() && i < 8; ++i) text += (i ? ", " : "") + option_text(value[i]);
    return text + (value.size() > 8 ? ", ...]" : "]");
  }
  if (value.is_object()) {
    std::string text = "{ ";
    bool first = true;
    for (const auto& [k, v] : value.items()) text += (first ? "" : ", ") + k + " = " + option_text(v), first = false;
    return text + " }";
  }
  std::string text = value.dump();
  return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

double option_number(const nlohmann::json& value) {
  if (value.is_number_unsigned()) return double(value.get<std::uint64_t>());
  if (value.is_number_integer()) return double(value.get<std::int64_t>());
  if (value.is_number()) return value.get<double>();
  return std::numeric_limits<double>::quiet_NaN();
}

void check_option(const OptionSpec& spec, const nlohmann::json& value, const std::string& key) {
  const auto fail = [&] { throw InputError(key, option_text(value), spec.allowed()); };
  using Type = OptionSpec::Type;
  switch (spec.type) {
    case Type::boolean:
      if (!value.is_boolean()) fail();
      break;
    case Type::word:
      if (!value.is_string() || std::find(spec.words.begin(), spec.words.end(), value.get<std::string>()) == spec.words.end()) fail();
      break;
    case Type::integer:
      if (!value.is_number_integer() || !spec.range.contains(option_number(value))) fail();
      break;
    case Type::number:
      if (!value.is_number() || !spec.range.contains(option_number(value))) fail();
      break;
    case Type::table: {
      if (!value.is_object()) fail();
      for (const auto& [name, v] : value.items()) {
        const OptionSpec* row = find_option(spec.rows, name);
        if (!row) throw InputError(key + "." + name, option_text(v), "a key of " + spec.allowed());
        check_option(*row, v, key + "." + name);
      }
      for (const OptionSpec& row : spec.rows)
        if (row.fallback.is_null() && row.default_note.empty() && !value.contains(row.key))
          throw InputError(key + "." + row.key, "(missing)", row.allowed() + " (required in " + key + ")");
      break;
    }
    case Type::custom: break;  // its row reads it
  }
}

void check_options(const OptionTable& table, const nlohmann::json& given, const std::string& path) {
  if (given.is_null()) return;
  if (!given.is_object()) throw InputError(path, option_text(given), "a table of options");
  for (const auto& [name, value] : given.items()) {
    const OptionSpec* spec = find_option(table, name);
    if (!spec) {
      std::vector<std::string> keys;
      for (const OptionSpec& s : table) keys.push_back(s.key);
      throw InputError(path + "." + name, option_text(value),
                       keys.empty() ? "no options here" : "unknown option; the options: " + join(keys));
    }
    check_option(*spec, value, path + "." + name);
  }
}

}  // namespace aggkit
