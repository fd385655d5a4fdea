// Reading a scan scene (scan_plan.hpp): the [scan] section here; [model], [time] and [[engine]] through the
// run-scene parser (scene.cpp), so they are validated exactly as for `aggkit run`.
#include "validation/scan/scan_plan.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "validation/scan/scan_point.hpp"
#include "validation/scene/scene_table.hpp"
#include "validation/scene/value_range.hpp"

namespace aggkit {

namespace {

constexpr std::size_t max_grid_values = 10'000;  // per axis; more is surely a typo

std::string toml_text(const toml::table& table) {
  std::ostringstream out;
  out << table;
  return out.str();
}

void check_increasing(const std::string& key, const std::vector<double>& values) {
  for (std::size_t i = 1; i < values.size(); ++i)
    if (!(values[i] > values[i - 1]))
      throw InputError(key + "[" + std::to_string(i) + "]", shortest_text(values[i]),
                       "values must increase; the previous one is " + shortest_text(values[i - 1]));
}

// A list of values or { from, to, count, spacing }. `log_spacing` reports the spacing of a range (lists: log
// when every ratio is the same, so that the λ_crit midpoint is geometric for log-spaced lists too).
std::vector<double> read_axis(const SceneTable& scan, const std::string& name, bool& log_spacing) {
  const toml::node* node = scan.find(name);
  const std::string forms = "a list of values or { from = .., to = .., count = .. (, spacing = \"log\") }";
  if (!node) scan.fail(name, "required: " + forms);
  std::vector<double> values;
  log_spacing = false;
  if (node->is_array()) {
    values = scan.numbers(name, Bound::finite);
    if (values.empty()) scan.fail(name, "at least one value (an empty list scans nothing)");
    if (values.size() > max_grid_values) scan.fail(name, "at most " + std::to_string(max_grid_values) + " values");
    check_increasing(scan.key(name), values);
    return values;
  }
  if (!node->is_table()) scan.fail(name, forms);
  return read_value_range(scan.table(name), max_grid_values, log_spacing);
}

std::vector<std::pair<double, double>> read_check_points(const SceneTable& check) {
  std::vector<std::pair<double, double>> points;
  const toml::node* node = check.find("points");
  if (!node) return points;
  const std::string expected = "a list of [a, lambda] pairs, e.g. [[0.95, 0.01]]";
  const toml::array* list = node->as_array();
  if (!list) check.fail("points", expected);
  for (std::size_t i = 0; i < list->size(); ++i) {
    const toml::array* pair = (*list)[i].as_array();
    const std::string key = check.key("points") + "[" + std::to_string(i) + "]";
    if (!pair || pair->size() != 2 || !(*pair)[0].is_number() || !(*pair)[1].is_number())
      throw InputError(key, scene_text((*list)[i]), expected);
    // value<double>() is empty for an integer a double cannot hold exactly (> 2^53): convert it ourselves.
    const auto number = [](const toml::node& n) {
      return n.is_integer() ? double(n.as_integer()->get()) : n.as_floating_point()->get();
    };
    points.emplace_back(number((*pair)[0]), number((*pair)[1]));
  }
  return points;
}

void check_a(const std::string& key, double a) {
  if (!(a >= 0 && a <= 1)) throw InputError(key, shortest_text(a), "the kernel exponent a must lie in [0, 1]");
}
void check_lambda(const std::string& key, double lambda) {
  if (!(lambda > 0) || !std::isfinite(lambda))
    throw InputError(key, shortest_text(lambda), "the shattering rate λ must be finite and > 0");
}

// [scan] a and lambda: values or ranges; a λ list with one ratio throughout counts as log-spaced.
void read_axes(const SceneTable& scan, ScanPlan& plan) {
  bool a_log = false;
  plan.a = read_axis(scan, "a", a_log);
  for (std::size_t i = 0; i < plan.a.size(); ++i) check_a(scan.key("a") + "[" + std::to_string(i) + "]", plan.a[i]);
  plan.lambda = read_axis(scan, "lambda", plan.lambda_log);
  for (std::size_t i = 0; i < plan.lambda.size(); ++i)
    check_lambda(scan.key("lambda") + "[" + std::to_string(i) + "]", plan.lambda[i]);
  if (plan.lambda.size() > 2 && !plan.lambda_log) {  // a list with one ratio throughout is log-spaced
    const double ratio = plan.lambda[1] / plan.lambda[0];
    bool geometric = true;
    for (std::size_t i = 2; i < plan.lambda.size(); ++i)
      geometric = geometric && std::abs(plan.lambda[i] / plan.lambda[i - 1] / ratio - 1) < 1e-9;
    const double step = plan.lambda[1] - plan.lambda[0];
    bool arithmetic = true;
    for (std::size_t i = 2; i < plan.lambda.size(); ++i)
      arithmetic = arithmetic && std::abs((plan.lambda[i] - plan.lambda[i - 1]) / step - 1) < 1e-9;
    plan.lambda_log = geometric && !arithmetic;
  }
}

// [scan] series, tail, stability, steady_match and refine: how each point's run is classified and checked.
void read_classification(const SceneTable& scan, std::size_t outputs, ScanPlan& plan) {
  plan.series = scan.optional_string("series").value_or("M0");
  if (plan.series == "M0") plan.series_order = 0;
  else if (plan.series == "M2") plan.series_order = 2;
  else scan.fail("series", "\"M0\" or \"M2\" (the moment whose time series is classified)");
  plan.criteria.tail_fraction = scan.optional_number("tail", Bound::positive).value_or(plan.criteria.tail_fraction);
  if (!(plan.criteria.tail_fraction < 1)) scan.fail("tail", "a fraction of the run in (0, 1)");
  const double tail_samples = plan.criteria.tail_fraction * double(outputs);
  if (tail_samples < 16)
    scan.fail("tail", "at least 16 outputs in the classified tail (it has about " +
                          std::to_string(int(tail_samples)) + "; raise tail or output more often)");
  plan.stability = scan.optional_boolean("stability").value_or(true);
  plan.steady_match = scan.optional_number("steady_match", Bound::positive).value_or(plan.steady_match);
  if (!(plan.steady_match < 1)) scan.fail("steady_match", "a fraction in (0, 1) of the steady state's value");
  plan.refine = scan.optional_boolean("refine").value_or(true);
}

// [scan] cycles, cycle_run, cycle_steps and confirm_run: the cycle search and the confirmation runs.
void read_cycle_search(const SceneTable& scan, ScanPlan& plan) {
  plan.cycles = scan.optional_boolean("cycles").value_or(true);
  plan.cycle_run = scan.optional_number("cycle_run", Bound::positive).value_or(plan.cycle_run);
  plan.cycle_steps = scan.optional_count("cycle_steps", 100).value_or(plan.cycle_steps);
  plan.confirm_run = scan.optional_number("confirm_run", Bound::positive).value_or(0.0);
  plan.column_periods = scan.optional_count("cycle_column", 10).value_or(0);
  plan.column_steps = scan.optional_count("column_steps", 100).value_or(0);
  if (plan.column_steps > 0 && plan.column_periods == 0)
    scan.fail("column_steps", "a step budget for the columns' runs with cycle_column set (there are no columns without it)");
  if (plan.column_periods > 0 && !(plan.stability && plan.cycles && plan.series_order == 0))
    scan.fail("cycle_column", "the cycles continued down the columns need stability = true, cycles = true and "
                              "series = \"M0\" (they start on the Hopf normal form's cycle and classify M0)");
  if (plan.confirm_run > 0 && !plan.stability)
    scan.fail("confirm_run", "confirmation runs sized by the spectrum need stability = true (without it the run "
                             "over [time] is the classification)");
}

}  // namespace

ScanPlan parse_scan_plan(std::string_view text, const std::string& source) {
  toml::table document = parse_toml_text(text, source);
  const SceneTable root(document, "");
  root.allow_only({"name", "tier", "model", "time", "engine", "scan"});
  if (!root.contains("scan")) root.fail("scan", "required in a scan scene: [scan] with a = .. and lambda = ..");
  if (!document.get("scan")->is_table()) root.fail("scan", "a table [scan]");
  const toml::table scan_table = *document.get("scan")->as_table();

  // The run-scene parser reads [model], [time] and [[engine]]; it wants [observe], which a scan does not use.
  toml::table run_part = document;
  run_part.erase("scan");
  if (!run_part.contains("engine")) {
    toml::array engines;
    engines.push_back(toml::table{{"name", "cvode"}});
    run_part.insert("engine", engines);
  }
  run_part.insert("observe", toml::table{{"series", toml::array{"M0", "M2"}}});
  ScanPlan plan;
  plan.scene = parse_scene(toml_text(run_part), source);

  const Scene& scene = plan.scene;
  if (scene.model.kernel.name() != "brownian")
    throw InputError("model.kernel.name", "\"" + scene.model.kernel.name() + "\"",
                     "a scan needs the brownian kernel (i/j)^a + (j/i)^a; its a is set by [scan] a");
  if (scene.engines.size() != 1 || scene.engines[0].name != "cvode")
    root.fail("engine", "at most one [[engine]], and it must be name = \"cvode\" (each point's integrator)");
  plan.engine = build_engine(scene, 0);
  const std::vector<double>& outputs = scene.time.outputs;
  if (outputs.size() < 32)
    throw InputError("time.every", std::to_string(outputs.size()) + " outputs",
                     "a scan classifies a sampled series: give at least 32 uniform outputs (time.every)");
  const double spacing = outputs.back() / double(outputs.size());  // outputs are k · every, k = 1..
  for (std::size_t i = 0; i < outputs.size(); ++i)
    if (std::abs(outputs[i] - double(i + 1) * spacing) > 1e-6 * spacing)
      throw InputError("time", "outputs up to " + shortest_text(scene.time.end),
                       "uniformly spaced outputs from t = every to the end: time.every dividing time.end");

  const SceneTable scan(scan_table, "scan");
  scan.allow_only({"a", "lambda", "series", "tail", "stability", "steady_match", "refine", "truncation_check", "hopf_grid",
                    "cycles", "cycle_run", "cycle_steps", "confirm_run", "cycle_column", "column_steps"});
  read_axes(scan, plan);
  if (plan.point_count() > max_grid_values * 10)
    scan.fail("lambda", "at most " + std::to_string(max_grid_values * 10) + " points in all (a × λ)");

  read_classification(scan, scene.time.outputs.size(), plan);
  read_cycle_search(scan, plan);
  plan.hopf_grid = scene.model.grid;
  if (scan.read_table("hopf_grid", size_grid_option_rows(), plan.hopf_grid)) {  // scheme: the model's unless given
    const auto key = [&](const std::string& k) { return scan.key("hopf_grid") + "." + k.substr(k.find('.') + 1); };
    under_key(key, [&] { plan.hopf_grid.validate(); });
  }

  if (const auto check = scan.optional_table("truncation_check")) {
    check->allow_only({"points", "lambda_crit"});
    plan.check_points = read_check_points(*check);
    for (std::size_t i = 0; i < plan.check_points.size(); ++i) {
      const std::string key = check->key("points") + "[" + std::to_string(i) + "]";
      check_a(key + "[0]", plan.check_points[i].first);
      check_lambda(key + "[1]", plan.check_points[i].second);
    }
    plan.check_lambda_crit = check->optional_boolean("lambda_crit").value_or(false);
  }

  // The fingerprint: everything but the name and the grid (whose points are matched by value).
  toml::table fingerprint = run_part;
  fingerprint.erase("name");
  toml::table scan_settings = scan_table;
  // refine only adds repeats, cached under their own names: the grid's results do not depend on it.
  // cycle_column and column_steps only add the columns' steps, cached under their own names with their settings.
  for (const char* key : {"a", "lambda", "truncation_check", "refine", "cycle_column", "column_steps"}) scan_settings.erase(key);
  fingerprint.insert("scan", scan_settings);
  plan.fingerprint = toml_text(fingerprint);
  plan.branches = make_steady_branches();
  return plan;
}

ScanPlan load_scan_plan(const std::filesystem::path& path) {
  ScanPlan plan = parse_scan_plan(read_scene_file(path), path.string());
  plan.scene.path = path;
  return plan;
}

ScanPlan refined_plan(const ScanPlan& plan) {
  ScanPlan fine = plan;
  fine.scene.model.grid = plan.scene.model.grid.refined();
  return fine;
}

AggregationModel point_model(const ScanPlan& plan, double a, double lambda, std::size_t size) {
  AggregationModel model = plan.scene.model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = size;  // a shorter initial table is padded with zeros (model.hpp)
  return model;
}

}  // namespace aggkit
