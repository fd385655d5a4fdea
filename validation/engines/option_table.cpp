#include "validation/engines/option_table.hpp"

#include <cmath>

#include "analysis/input_error.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

std::string bound_text(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return shortest_text(x);
}

}  // namespace

std::string OptionSpec::allowed() const {
  switch (type) {
    case Type::boolean: return "true or false";
    case Type::word: return "one of " + join(words);
    case Type::custom: return forms;
    case Type::integer:
      if (std::isinf(maximum) || maximum >= 9e15) return "an integer >= " + bound_text(minimum);
      return "an integer in " + bound_text(minimum) + ".." + bound_text(maximum);
    case Type::number: {
      const bool low = std::isfinite(minimum), high = std::isfinite(maximum);
      if (low && high) return "a number in " + std::string(above ? "(" : "[") + bound_text(minimum) + ", " + bound_text(maximum) + "]";
      if (low) return "a finite number " + std::string(above ? "> " : ">= ") + bound_text(minimum);
      if (high) return "a finite number <= " + bound_text(maximum);
      return "a finite number";
    }
  }
  return "";
}

OptionSpec flag_option(std::string key, bool fallback, std::string doc) {
  OptionSpec s;
  s.key = std::move(key), s.type = OptionSpec::Type::boolean, s.default_text = fallback ? "true" : "false";
  s.doc = std::move(doc);
  return s;
}

OptionSpec integer_option(std::string key, std::string fallback, std::string doc, double minimum, double maximum) {
  OptionSpec s;
  s.key = std::move(key), s.type = OptionSpec::Type::integer, s.default_text = std::move(fallback);
  s.doc = std::move(doc), s.minimum = minimum, s.maximum = maximum;
  return s;
}

OptionSpec number_option(std::string key, std::string fallback, std::string doc, double minimum, double maximum, bool above) {
  OptionSpec s;
  s.key = std::move(key), s.type = OptionSpec::Type::number, s.default_text = std::move(fallback);
  s.doc = std::move(doc), s.minimum = minimum, s.maximum = maximum, s.above = above;
  return s;
}

OptionSpec word_option(std::string key, std::string fallback, std::string doc, std::vector<std::string> words) {
  OptionSpec s;
  s.key = std::move(key), s.type = OptionSpec::Type::word, s.default_text = std::move(fallback);
  s.doc = std::move(doc), s.words = std::move(words);
  return s;
}

OptionSpec custom_option(std::string key, std::string fallback, std::string doc, std::string forms) {
  OptionSpec s;
  s.key = std::move(key), s.type = OptionSpec::Type::custom, s.default_text = std::move(fallback);
  s.doc = std::move(doc), s.forms = std::move(forms);
  return s;
}

std::string option_text(const nlohmann::json& value) {
  if (value.is_number_float()) return float_text(value.get<double>());
  if (value.is_string()) return "\"" + printable_text(value.get<std::string>()) + "\"";
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

EngineOptions::EngineOptions(const OptionTable& table, const nlohmann::json& given, std::string path)
    : table_(&table), given_(given.is_null() ? nlohmann::json::object() : given), path_(std::move(path)) {
  if (!given_.is_object()) throw InputError(path_, option_text(given_), "a table of options");
  for (const auto& [name, value] : given_.items()) {
    const OptionSpec* spec = nullptr;
    for (const OptionSpec& s : table) if (s.key == name) spec = &s;
    if (!spec) {
      std::vector<std::string> keys;
      for (const OptionSpec& s : table) keys.push_back(s.key);
      throw InputError(key(name), option_text(value),
                       keys.empty() ? "this engine has no options besides name and label"
                                    : "unknown option; the options besides name and label: " + join(keys));
    }
    using Type = OptionSpec::Type;
    switch (spec->type) {
      case Type::boolean:
        if (!value.is_boolean()) fail(name, spec->allowed());
        break;
      case Type::word:
        if (!value.is_string()) fail(name, spec->allowed());
        if (std::find(spec->words.begin(), spec->words.end(), value.get<std::string>()) == spec->words.end())
          fail(name, spec->allowed());
        break;
      case Type::integer: {
        if (!value.is_number_integer()) fail(name, spec->allowed());
        const double x = value.is_number_unsigned() ? double(value.get<std::uint64_t>()) : double(value.get<std::int64_t>());
        if (x < spec->minimum || x > spec->maximum) fail(name, spec->allowed());
        break;
      }
      case Type::number: {
        if (!value.is_number()) fail(name, spec->allowed());
        const double x = value.get<double>();
        if (!std::isfinite(x) || x < spec->minimum || (spec->above && x == spec->minimum) || x > spec->maximum)
          fail(name, spec->allowed());
        break;
      }
      case Type::custom: break;  // the engine reads it
    }
  }
}

const OptionSpec& EngineOptions::spec(std::string_view key) const {
  for (const OptionSpec& s : *table_)
    if (s.key == key) return s;
  throw std::logic_error("engine option " + std::string(key) + " is not in the engine's table");
}

bool EngineOptions::boolean(std::string_view key, bool fallback) const {
  (void)spec(key);
  return has(key) ? given_.at(std::string(key)).get<bool>() : fallback;
}

std::int64_t EngineOptions::integer(std::string_view key, std::int64_t fallback) const {
  (void)spec(key);
  return has(key) ? given_.at(std::string(key)).get<std::int64_t>() : fallback;
}

double EngineOptions::number(std::string_view key, double fallback) const {
  (void)spec(key);
  return has(key) ? given_.at(std::string(key)).get<double>() : fallback;
}

std::string EngineOptions::word(std::string_view key, const std::string& fallback) const {
  (void)spec(key);
  return has(key) ? given_.at(std::string(key)).get<std::string>() : fallback;
}

const nlohmann::json& EngineOptions::value(std::string_view key) const {
  (void)spec(key);
  return given_.at(std::string(key));
}

void EngineOptions::fail(std::string_view name, const std::string& allowed) const {
  const std::string n(name);
  throw InputError(key(name), given_.contains(n) ? option_text(given_.at(n)) : "(missing)", allowed);
}

}  // namespace aggkit
