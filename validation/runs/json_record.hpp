#pragma once
// A record file of one JSON object (the sweep's points, validate's finished scenes): the object, or nullopt for
// anything else — empty, damaged, truncated or not an object is not a record, and its run is done again. The
// one-row CSV records are read by one_row_record (run_store.hpp). Header-only, so that only the readers of
// JSON records depend on nlohmann/json.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace aggkit {

inline std::optional<nlohmann::json> json_record(const std::string& text) {
  if (text.empty()) return std::nullopt;
  nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object()) return std::nullopt;  // a parse error is `discarded`, not an object
  return json;
}

}  // namespace aggkit
