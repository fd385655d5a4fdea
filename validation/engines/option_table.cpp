#include "validation/engines/option_table.hpp"

#include "analysis/text.hpp"

namespace aggkit {

EngineOptions::EngineOptions(const OptionTable& table, const nlohmann::json& given, std::string path)
    : given_(given.is_null() ? nlohmann::json::object() : given), path_(std::move(path)) {
  if (!given_.is_object()) throw InputError(path_, option_text(given_), "a table of options");
  for (const auto& [name, value] : given_.items()) {
    const OptionSpec* spec = find_option(table, name);
    if (!spec) {
      std::vector<std::string> keys;
      for (const OptionSpec& s : table) keys.push_back(s.key);
      throw InputError(key(name), option_text(value),
                       keys.empty() ? "this engine has no options besides name and label"
                                    : "unknown option; the options besides name and label: " + join(keys));
    }
    check_option(*spec, value, key(name));
  }
}

void EngineOptions::fail(std::string_view name, const std::string& allowed) const {
  const std::string n(name);
  throw InputError(key(name), given_.contains(n) ? option_text(given_.at(n)) : "(missing)", allowed);
}

}  // namespace aggkit
