#pragma once
// Options declared once, bound to the fields they set (as REBOUND binds a field descriptor to a struct
// offset). A row holds an option's key, type, allowed range and one line of documentation, and names the
// field of a settings struct it sets (a member pointer, or an accessor for a nested field); its default is
// that field's value in a default-constructed struct. One set of rows gives
//   * the range check of the library's own validate(): OptionRows::check (a C++ caller gets it too),
//   * the check of a scene's or a Python call's values (check_option: type, range, the keys of a sub-table)
//     and their reading into the settings (OptionRows::apply),
//   * the values a run uses (OptionRows::values), and the table `aggkit run --help` and Python print
//     (OptionRows::table: the default as text, derived from the value unless the default is computed).
// The rows live with the physics they configure (solvers/, particle/<engine>/); the harness only joins them
// into an engine's table (validation/engines/option_table.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"

namespace aggkit {

// The allowed interval of a number or an integer option.
struct Range {
  double minimum = -std::numeric_limits<double>::infinity();
  double maximum = std::numeric_limits<double>::infinity();
  bool above = false;  // the minimum itself is excluded
  bool below = false;  // the maximum itself is excluded
  bool contains(double x) const {
    return std::isfinite(x) && (above ? x > minimum : x >= minimum) && (below ? x < maximum : x <= maximum);
  }
};
inline constexpr double largest_integer = 9.007199254740992e15;  // 2^53: the integers a double holds exactly
inline Range at_least(double a) { return {a, std::numeric_limits<double>::infinity(), false, false}; }
inline Range greater_than(double a) { return {a, std::numeric_limits<double>::infinity(), true, false}; }
inline Range closed(double a, double b) { return {a, b, false, false}; }     // [a, b]
inline Range left_open(double a, double b) { return {a, b, true, false}; }   // (a, b]
inline Range right_open(double a, double b) { return {a, b, false, true}; }  // [a, b)
inline Range open(double a, double b) { return {a, b, true, true}; }         // (a, b)

struct OptionSpec {
  enum class Type { boolean, integer, number, word, table, custom };
  std::string key;
  Type type = Type::number;
  std::string doc;                 // one line
  nlohmann::json fallback;         // the field's value in default-constructed settings (null: none)
  std::string default_note;        // a computed default ("rtol/100") or what a missing key means ("none")
  Range range;                     // integer, number
  std::vector<std::string> words;  // word: the allowed values
  std::string forms;               // custom: what is allowed (its row's setter checks it)
  std::vector<OptionSpec> rows;    // table: its keys

  std::string allowed() const;       // "a number > 0", "an integer in 1..10000", "one of a, b", "a table of ..."
  std::string default_text() const;  // as --help shows it: the note if any, else the value ("1e-06", "bdf-gmres")
};
using OptionTable = std::vector<OptionSpec>;

const OptionSpec* find_option(const OptionTable& table, std::string_view key);  // nullptr if absent
// The text of a JSON value as a scene writes it (strings quoted, numbers shortest, nan as nan).
std::string option_text(const nlohmann::json& value);
// The value of a number or integer option as a double (a JSON number; NaN for anything else).
double option_number(const nlohmann::json& value);
// Throws InputError naming `key`, the value and spec.allowed() unless `value` has the row's type and lies in
// its range; a table's keys are checked against its rows ("key.sub"). Custom values are left to the row.
void check_option(const OptionSpec& spec, const nlohmann::json& value, const std::string& key);
// The same for a table of options given as one JSON object: unknown keys are refused listing the known ones.
void check_options(const OptionTable& table, const nlohmann::json& given, const std::string& path);

// One option bound to settings of type S.
template <class S>
struct OptionRow {
  OptionSpec spec;
  std::function<nlohmann::json(const S&)> get;                                  // null: none
  std::function<void(S&, const nlohmann::json&, const std::string& key)> set;  // a value check_option passed
  std::vector<OptionRow<S>> rows;                                               // table: its keys
  std::function<bool(const S&)> present;  // table: whether the settings hold it (then its rows are checked)
  bool required = false;  // in a sub-table: must be given (no default, though the field has a value)
};

// The rows of settings S; the defaults are read from S{}.
template <class S>
class OptionRows {
 public:
  OptionRows(std::vector<OptionRow<S>> rows) : rows_(std::move(rows)) { fill_defaults(rows_, S{}); }

  const std::vector<OptionRow<S>>& rows() const { return rows_; }
  OptionTable table() const { return specs(rows_); }

  // Sets the field of every key of `given` (a JSON object already checked by check_options) that has a row
  // here; other keys are left to other rows. `path` names the table in messages ("engine[1]").
  void apply(const nlohmann::json& given, S& settings, const std::string& path) const { apply(rows_, given, settings, path); }

  // The library's range check: InputError (key "path.key", or "key" without a path) for a bound field
  // outside its row's range.
  void check(const S& settings, const std::string& path = "") const { check(rows_, settings, path); }

  // The values the settings hold, key -> value (sub-tables nested; keys without a value left out).
  nlohmann::json values(const S& settings) const { return values(rows_, settings); }

 private:
  static std::string join_key(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
  static void fill_defaults(std::vector<OptionRow<S>>& rows, const S& defaults) {
    for (OptionRow<S>& row : rows) {
      if (row.get && !row.required) row.spec.fallback = row.get(defaults);
      fill_defaults(row.rows, defaults);
      row.spec.rows = specs(row.rows);
    }
  }
  static OptionTable specs(const std::vector<OptionRow<S>>& rows) {
    OptionTable table;
    for (const OptionRow<S>& row : rows) table.push_back(row.spec);
    return table;
  }
  static void apply(const std::vector<OptionRow<S>>& rows, const nlohmann::json& given, S& settings, const std::string& path) {
    for (const OptionRow<S>& row : rows) {
      const auto it = given.find(row.spec.key);
      if (it == given.end()) continue;
      const std::string key = join_key(path, row.spec.key);
      if (row.set) row.set(settings, *it, key);
      if (row.spec.type == OptionSpec::Type::table) apply(row.rows, *it, settings, key);
    }
  }
  static void check(const std::vector<OptionRow<S>>& rows, const S& settings, const std::string& path) {
    for (const OptionRow<S>& row : rows) {
      const std::string key = join_key(path, row.spec.key);
      if (row.spec.type == OptionSpec::Type::table) {
        if (!row.present || row.present(settings)) check(row.rows, settings, key);
        continue;
      }
      if (row.spec.type != OptionSpec::Type::number && row.spec.type != OptionSpec::Type::integer) continue;
      const nlohmann::json value = row.get(settings);
      if (!value.is_null() && !row.spec.range.contains(option_number(value)))
        throw InputError(key, option_text(value), row.spec.allowed());
    }
  }
  static nlohmann::json values(const std::vector<OptionRow<S>>& rows, const S& settings) {
    nlohmann::json out = nlohmann::json::object();
    for (const OptionRow<S>& row : rows) {
      if (row.spec.type == OptionSpec::Type::table) {
        if (!row.present || row.present(settings)) out[row.spec.key] = values(row.rows, settings);
      } else if (row.get) {
        nlohmann::json value = row.get(settings);
        if (!value.is_null()) out[row.spec.key] = std::move(value);
      }
    }
    return out;
  }

  std::vector<OptionRow<S>> rows_;
};

// Row builders for settings S. `field` is a member pointer (&S::rtol) or an accessor returning a reference
// to the field, callable on S& and const S& ([](auto& s) -> auto& { return s.daha.c_bar; }). A field of
// type std::optional<T> has no default (null): give `default_note` to say what its absence means.
template <class S>
struct Bind {
  template <class F>
  static OptionRow<S> number(std::string key, F field, Range range, std::string doc, std::string default_note = "") {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::number, std::move(doc), std::move(default_note));
    row.spec.range = range;
    row.get = [field](const S& s) { return to_json(std::invoke(field, s)); };
    row.set = [field](S& s, const nlohmann::json& value, const std::string&) { std::invoke(field, s) = value.get<double>(); };
    return row;
  }
  template <class F>
  static OptionRow<S> integer(std::string key, F field, Range range, std::string doc, std::string default_note = "") {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::integer, std::move(doc), std::move(default_note));
    using T = std::remove_cvref_t<decltype(*optional_value(std::invoke(field, std::declval<S&>())))>;
    range.minimum = std::max(range.minimum, double(std::numeric_limits<T>::lowest()));  // what the field holds
    range.maximum = std::min(range.maximum, double(std::numeric_limits<T>::max()));
    row.spec.range = range;
    row.get = [field](const S& s) { return to_json(std::invoke(field, s)); };
    row.set = [field](S& s, const nlohmann::json& value, const std::string&) {
      auto& target = std::invoke(field, s);
      using T = std::remove_cvref_t<decltype(target)>;
      target = value.is_number_unsigned() ? T(value.get<std::uint64_t>()) : T(value.get<std::int64_t>());
    };
    return row;
  }
  template <class F>
  static OptionRow<S> flag(std::string key, F field, std::string doc) {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::boolean, std::move(doc), "");
    row.get = [field](const S& s) { return nlohmann::json(bool(std::invoke(field, s))); };
    row.set = [field](S& s, const nlohmann::json& value, const std::string&) { std::invoke(field, s) = value.get<bool>(); };
    return row;
  }
  // A word naming one of `choices` (an enum, a bool, ...): the field holds the chosen value.
  template <class F, class V>
  static OptionRow<S> word(std::string key, F field, std::vector<std::pair<std::string, V>> choices, std::string doc) {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::word, std::move(doc), "");
    for (const auto& choice : choices) row.spec.words.push_back(choice.first);
    row.get = [field, choices](const S& s) {
      for (const auto& [name, value] : choices)
        if (std::invoke(field, s) == value) return nlohmann::json(name);
      return nlohmann::json();
    };
    row.set = [field, choices](S& s, const nlohmann::json& value, const std::string&) {
      for (const auto& [name, v] : choices)
        if (value.get<std::string>() == name) std::invoke(field, s) = v;
    };
    return row;
  }
  // A word naming a value of an enum with to_string(E).
  template <class F, class E>
  static OptionRow<S> named(std::string key, F field, std::vector<E> values, std::string doc) {
    std::vector<std::pair<std::string, E>> choices;
    for (E value : values) choices.emplace_back(to_string(value), value);
    return word(std::move(key), std::move(field), std::move(choices), std::move(doc));
  }
  // A value of its own forms, read by `set` (InputError naming the key for one it refuses).
  static OptionRow<S> custom(std::string key, std::string forms, std::string doc, std::string default_note,
                             std::function<nlohmann::json(const S&)> get,
                             std::function<void(S&, const nlohmann::json&, const std::string& key)> set) {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::custom, std::move(doc), std::move(default_note));
    row.spec.forms = std::move(forms);
    row.get = std::move(get), row.set = std::move(set);
    return row;
  }
  // `row` as a key a sub-table must give: no default is printed or assumed.
  static OptionRow<S> required(OptionRow<S> row) {
    row.required = true;
    return row;
  }
  // A sub-table of options (key = { a = .., b = .. }); `on` is called when it is given (before its rows are
  // read), `present` tells whether the settings hold it.
  static OptionRow<S> table(std::string key, std::string doc, std::string default_note, std::vector<OptionRow<S>> rows,
                            std::function<bool(const S&)> present, std::function<void(S&)> on) {
    OptionRow<S> row = make(std::move(key), OptionSpec::Type::table, std::move(doc), std::move(default_note));
    row.rows = std::move(rows);
    row.present = std::move(present);
    row.set = [on](S& s, const nlohmann::json&, const std::string&) { on(s); };
    return row;
  }

 private:
  static OptionRow<S> make(std::string key, OptionSpec::Type type, std::string doc, std::string default_note) {
    OptionRow<S> row;
    row.spec.key = std::move(key), row.spec.type = type, row.spec.doc = std::move(doc);
    row.spec.default_note = std::move(default_note);
    return row;
  }
  template <class T>
  static const T* optional_value(const T& value) { return &value; }
  template <class T>
  static const T* optional_value(const std::optional<T>& value) { return value ? &*value : nullptr; }
  template <class T>
  static nlohmann::json to_json(const T& value) {
    if constexpr (requires { value.has_value(); }) return value ? nlohmann::json(*value) : nlohmann::json();
    else return nlohmann::json(value);
  }
};

}  // namespace aggkit
