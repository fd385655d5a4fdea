// Every engine's option table, row by row: the default `aggkit run --help` prints is the value a built
// engine runs with (and giving it explicitly changes nothing), a value just outside each printed bound is
// refused naming the key, and one just inside is accepted. The rows are the only declaration of an option
// (analysis/option_rows.hpp), so this walks whatever the engines declare, sub-tables included.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "analysis/input_error.hpp"
#include "analysis/option_rows.hpp"
#include "analysis/text.hpp"
#include "particle/dsmc/options.hpp"
#include "particle/ed/ed_options.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/size_grid.hpp"
#include "solvers/steady_state_options.hpp"
#include "validation/engines/engine.hpp"
#include "validation/scene/scene_table.hpp"

using namespace aggkit;

namespace {

// The smallest scene each engine kind builds on, and the options it needs besides the one under test.
struct Base {
  std::string scene;      // up to and including `name = "<engine>"`
  std::string observe;
  nlohmann::json options;  // always given
};

Base base(const std::string& engine) {
  const std::string kinetic = "name = \"rows\"\n[model]\nkernel = { name = \"constant\" }\nlambda = " +
                              std::string(engine == "snes" ? "0.1" : "0.0") + "\nsize = 64\n[time]\nend = 2.0\noutputs = [1.0]\n";
  const std::string hard_spheres = "name = \"rows\"\n[particles]\ndimension = 2\ncount = 100\nradius = 0.5\nvolume_fraction = 0.2\n"
                                   "boundary = \"reflecting\"\ninitial = { lattice = \"square\", speed = 1.0 }\n[time]\nend = 1.0\noutputs = [1.0]\n";
  const std::string cloud = "name = \"rows\"\n[particles]\ndimension = 3\ncount = 100\nradius = 1.0\nmass = 1.0\nboundary = \"open\"\n"
                            "initial = { cloud = \"cube\", volume_fraction = 0.05, speed = 0.0 }\n[time]\nend = 1.0\noutputs = [1.0]\n";
  if (engine == "ed" || engine == "ts") return {hard_spheres, "series = [\"clusters\"]\n", nlohmann::json::object()};
  if (engine == "dem")
    return {cloud, "series = [\"clusters\"]\n", {{"restitution", 0.5}, {"contact_time", 0.05}, {"gravity", {{"G", 1.0}}}}};
  return {kinetic, "series = [\"M0\"]\n", nlohmann::json::object()};
}

std::string scene_text(const std::string& engine, const nlohmann::json& options) {
  const Base b = base(engine);
  std::string text = b.scene + "[[engine]]\nname = \"" + engine + "\"\n";
  for (const auto& [key, value] : options.items()) text += key + " = " + option_text(value) + "\n";
  return text + "[observe]\n" + b.observe;
}

nlohmann::json settings_with(const std::string& engine, const nlohmann::json& options) {
  return build_engine(parse_scene(scene_text(engine, options)), 0)->settings();
}

// The options for one test of `key` (a dotted path into a sub-table: "gravity.G") at `value`: the base
// options, with `companions` what the row needs beside it at the ends of its range, and the value.
nlohmann::json options_for(const std::string& engine, const std::string& key, const nlohmann::json& value,
                           bool companions = true) {
  nlohmann::json options = base(engine).options;
  if (!companions) {
    options[key] = value;
    return options;
  }
  if (engine == "dem" && (key == "stiffness" || key == "damping" || key == "stiffness_normalized")) {
    options.erase("restitution"), options.erase("contact_time");
    if (key != "damping") options["damping"] = 0.0;  // an elastic law: the damping ratio stays finite
    if (key == "damping") options["stiffness"] = 1e4;
  }
  if (engine == "dem" && key == "gravity.opening_angle") options["gravity"]["method"] = "tree";
  // The damping of one DAHA iteration δ c̄ is at most 1: the other factor small at either's largest value.
  if (engine == "ts" && key == "c_bar") options["delta"] = 1e-7;
  if (engine == "ts" && key == "delta") options["c_bar"] = 0.05;
  if (const auto dot = key.find('.'); dot != std::string::npos)
    options[key.substr(0, dot)][key.substr(dot + 1)] = value;
  else
    options[key] = value;
  return options;
}

// What `--help` prints as the default, read back as the value it names.
nlohmann::json printed_value(const OptionSpec& row) {
  const std::string text = row.default_text();
  switch (row.type) {
    case OptionSpec::Type::boolean: return text == "true";
    case OptionSpec::Type::integer: return std::stoll(text);
    case OptionSpec::Type::number: return std::stod(text);
    case OptionSpec::Type::word: return text;
    default: return text;  // compared as option_text
  }
}

void check_defaults(const std::string& engine, const OptionTable& rows, const nlohmann::json& used, const std::string& path) {
  const std::string help = engines_help();
  for (const OptionSpec& row : rows) {
    const std::string key = path + row.key;
    INFO(engine << " " << key << " (default " << row.default_text() << ")");
    if (path.empty())
      CHECK_THAT(help, Catch::Contains("    " + row.key + " (default " + row.default_text() + "; " + row.allowed() + "): " + row.doc + "\n"));
    if (row.type == OptionSpec::Type::table) {
      if (used.contains(row.key)) check_defaults(engine, row.rows, used[row.key], key + ".");
      continue;
    }
    if (!row.default_note.empty() || row.fallback.is_null()) continue;  // computed at run time, or none
    REQUIRE(used.contains(row.key));
    if (row.type == OptionSpec::Type::custom)
      CHECK(option_text(used[row.key]) == row.default_text());
    else
      CHECK(used[row.key] == printed_value(row));
  }
}

struct Probe {
  double value;
  bool allowed;
};

// Just outside and just inside each finite bound of a number or integer row.
std::vector<Probe> probes_of(const OptionSpec& row) {
  const bool integer = row.type == OptionSpec::Type::integer;
  const Range& r = row.range;
  std::vector<Probe> probes;
  const double inf = std::numeric_limits<double>::infinity();
  if (std::isfinite(r.minimum) && std::abs(r.minimum) < largest_integer) {
    if (integer) probes.push_back({r.minimum - 1, false}), probes.push_back({r.minimum, true});
    // Inside an excluded bound by one part in 10^9 (the next double above 0 would overflow the physics:
    // k_n = m*(π² + ln² e)/t_c² at t_c = 5e-324).
    else if (r.above) probes.push_back({r.minimum, false}), probes.push_back({r.minimum + 1e-9 * std::max(1.0, std::abs(r.minimum)), true});
    else probes.push_back({std::nextafter(r.minimum, -inf), false}), probes.push_back({r.minimum, true});
  }
  if (std::isfinite(r.maximum) && std::abs(r.maximum) < largest_integer) {
    if (integer) probes.push_back({r.maximum + 1, false}), probes.push_back({r.maximum, true});
    else if (r.below) probes.push_back({r.maximum, false}), probes.push_back({std::nextafter(r.maximum, -inf), true});
    else probes.push_back({std::nextafter(r.maximum, inf), false}), probes.push_back({r.maximum, true});
  }
  return probes;
}

nlohmann::json probe_value(const OptionSpec& row, const Probe& probe) {
  return row.type == OptionSpec::Type::integer ? nlohmann::json(std::int64_t(probe.value)) : nlohmann::json(probe.value);
}

// Each bound of every number and integer row (sub-tables included), through a scene.
void check_ranges(const std::string& engine, const OptionTable& rows, const std::string& path) {
  for (const OptionSpec& row : rows) {
    const std::string key = path + row.key;
    if (row.type == OptionSpec::Type::table) check_ranges(engine, row.rows, key + ".");
    if (row.type != OptionSpec::Type::number && row.type != OptionSpec::Type::integer) continue;
    for (const Probe& probe : probes_of(row)) {
      const nlohmann::json value = probe_value(row, probe);
      const std::string text = scene_text(engine, options_for(engine, key, value));
      INFO(engine << " " << key << " = " << option_text(value) << " (" << row.allowed() << ")\n" << text);
      try {
        (void)build_engine(parse_scene(text), 0);
        CHECK(probe.allowed);
      } catch (const InputError& e) {
        INFO(e.what());
        // The one refusal inside a printed range: a DSMC population this machine cannot hold (check_memory).
        const bool machine_limit = engine == "dsmc" && key == "particles" && probe.value == 1e12 &&
                                   std::string(e.what()).find("a size this machine can hold") != std::string::npos;
        CHECK((!probe.allowed || machine_limit));
        if (!probe.allowed) CHECK(e.key() == "engine[0]." + key);
      }
    }
  }
}

// A library's validate() against its rows, without a scene: each bound of every number and integer row of
// `rows`, set through the row on `base`, is refused (naming the row's key) just outside and accepted just
// inside, so validate() and the rows cannot disagree. Values the field cannot hold are skipped.
template <class S>
void check_validate(const OptionRows<S>& rows, const S& base, const std::string& what) {
  for (const OptionRow<S>& row : rows.rows()) {
    if (row.spec.type != OptionSpec::Type::number && row.spec.type != OptionSpec::Type::integer) continue;
    for (const Probe& probe : probes_of(row.spec)) {
      S settings = base;
      row.set(settings, probe_value(row.spec, probe), row.spec.key);
      if (option_number(row.get(settings)) != probe.value) continue;
      INFO(what << " " << row.spec.key << " = " << option_text(row.get(settings)) << " (" << row.spec.allowed() << ")");
      try {
        settings.validate();
        CHECK(probe.allowed);
      } catch (const InputError& e) {
        INFO(e.what());
        CHECK(!probe.allowed);
        CHECK(leaf_key(e.key()) == row.spec.key);
      }
    }
  }
}

}  // namespace

TEST_CASE("option rows: the printed default is the value a run uses, and giving it changes nothing", "[options]") {
  for (const EngineType& type : engine_types()) {
    const nlohmann::json used = settings_with(type.name, base(type.name).options);
    check_defaults(type.name, type.options, used, "");
    for (const OptionSpec& row : type.options) {
      if (!row.default_note.empty() || row.fallback.is_null() || row.type == OptionSpec::Type::table) continue;
      INFO(type.name << " " << row.key << " = " << option_text(row.fallback));
      CHECK(settings_with(type.name, options_for(type.name, row.key, row.fallback, false)) == used);
    }
  }
}

TEST_CASE("option rows: a value just outside each printed bound is refused, one just inside accepted", "[options]") {
  for (const EngineType& type : engine_types()) check_ranges(type.name, type.options, "");
}

TEST_CASE("option rows: the library's own validate() is the rows' range check", "[options]") {
  // A C++ caller that never reads a scene gets the same check, naming the option.
  IntegratorOptions cvode;
  cvode.rtol = 1.0;  // (0, 1): once allowed by the scene's table and refused by the integrator
  try {
    cvode.validate();
    FAIL("rtol = 1 accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "rtol");
    CHECK_THAT(e.what(), Catch::Contains("(0, 1)"));
  }
  dsmc::Options d;
  d.bucket = (1u << 26) + 1;
  CHECK_THROWS_AS(d.validate(), InputError);
  d.bucket = 1u << 26;
  CHECK_NOTHROW(d.validate());
}

TEST_CASE("option rows: validate() refuses exactly what the rows' ranges refuse, at each bound", "[options]") {
  check_validate(steady_state_option_rows(), SteadyStateOptions{}, "snes");
  check_validate(steady_state_tuning_rows(), SteadyStateOptions{}, "snes (tuning)");
  check_validate(integrator_option_rows(), IntegratorOptions{}, "cvode");
  check_validate(dsmc::option_rows(), dsmc::Options{}, "dsmc");
  check_validate(ed_option_rows(), EdSettings{}, "ed");
  SizeGrid graded;
  graded.resolved = 64, graded.ratio = 1.05;
  check_validate(size_grid_option_rows(), graded, "grid");
}

TEST_CASE("option rows: a sub-table's keys, types and required keys are checked", "[options]") {
  struct S {
    double a = 1;
    std::optional<double> b;
    bool on = false;
  };
  const OptionRows<S> rows{{Bind<S>::table("t", "a table", "off",
                                           {Bind<S>::number("a", &S::a, closed(0, 2), "a"), Bind<S>::number("b", &S::b, greater_than(0), "b")},
                                           [](const S& s) { return s.on; }, [](S& s) { s.on = true; })}};
  const OptionTable table = rows.table();
  CHECK(table[0].allowed() == "a table { a = a number in [0, 2] (default 1), b = a finite number > 0 (required) }");
  CHECK_THROWS_WITH(check_options(table, {{"t", {{"a", 1.0}}}}, "e"), Catch::Contains("e.t.b = (missing)"));
  CHECK_THROWS_WITH(check_options(table, {{"t", {{"b", 1.0}, {"c", 1.0}}}}, "e"), Catch::Contains("e.t.c = 1.0"));
  CHECK_THROWS_WITH(check_options(table, {{"t", {{"b", 1.0}, {"a", 3.0}}}}, "e"), Catch::Contains("e.t.a = 3.0"));
  const nlohmann::json given = {{"t", {{"b", 0.5}}}};
  check_options(table, given, "e");
  S s;
  rows.apply(given, s, "e");
  CHECK(s.on);
  CHECK(s.b == 0.5);
  CHECK(rows.values(s) == nlohmann::json{{"t", {{"a", 1.0}, {"b", 0.5}}}});
  s.a = 3;  // the library check of a sub-table present in the settings
  CHECK_THROWS_WITH(rows.check(s), Catch::Contains("t.a = 3.0"));
}
