// [model]: kernel, shattering rate λ(t), truncation, size grid and initial condition.
#include <cmath>
#include <map>

#include "validation/scene/scene_sections.hpp"

namespace aggkit {

namespace {

// grid = { resolved = K, ratio = r, scheme = "four-moment" | "three-moment" | "fixed-pivot" }: the rows of
// solvers/size_grid.hpp; absent: the uniform grid.
SizeGrid read_grid(const SceneTable& model) {
  SizeGrid grid;
  if (model.read_table("grid", size_grid_option_rows(), grid)) under_key(model_key, [&] { grid.validate(); });
  return grid;
}

// The kernel checks its own name and parameters (solvers/kernels.hpp); values are read here as numbers.
Kernel read_kernel(const SceneTable& model) {
  const SceneTable kernel = model.table("kernel");
  const std::string name = kernel.string("name");
  std::map<std::string, double> parameters;
  for (auto&& [key, value] : kernel.raw())
    if (key.str() != "name") parameters[std::string(key.str())] = kernel.number(key.str(), Bound::any);
  return under_key(model_key, [&] { return Kernel::from_name(name, parameters); });
}

// λ = number | { initial, slope } | { times, values } (solvers/shattering_rate.hpp); its values are
// checked with the rest of the model (AggregationModel::validate).
ShatteringRate read_shattering_rate(const SceneTable& model) {
  const toml::node* node = model.find("lambda");
  if (!node) return ShatteringRate();  // pure aggregation
  const std::string forms = "a number >= 0, { initial = .., slope = .. } or { times = [..], values = [..] }";
  if (node->is_integer() || node->is_floating_point()) {
    const double lambda = model.number("lambda", Bound::any);
    return under_key(model_key, [&] { return ShatteringRate::constant(lambda); });
  }
  if (!node->is_table()) model.fail("lambda", forms);
  const SceneTable form = model.table("lambda");
  form.allow_only({"initial", "slope", "times", "values"});
  const bool linear = form.contains("initial") || form.contains("slope");
  const bool table = form.contains("times") || form.contains("values");
  if (linear == table) model.fail("lambda", forms);
  if (linear) {
    const double initial = form.number("initial", Bound::any), slope = form.number("slope", Bound::any);
    return under_key(model_key, [&] { return ShatteringRate::linear(initial, slope); });
  }
  const std::vector<double> times = form.numbers("times", Bound::any), values = form.numbers("values", Bound::any);
  return under_key(model_key, [&] { return ShatteringRate::table(times, values); });
}

std::vector<double> read_initial(const SceneTable& model, InitialCondition& initial) {
  const std::optional<SceneTable> table = model.optional_table("initial");
  // The monodisperse start is the one-entry table (shorter tables are zeros beyond, solvers/model.hpp): a
  // graded grid's N may be far beyond what a per-size table can hold.
  if (!table) return monodisperse(1);
  const std::string kind = table->string("kind");
  if (kind == "monodisperse") {
    table->allow_only({"kind", "density"});
    initial.kind = InitialCondition::Kind::monodisperse;
    initial.density = table->optional_number("density", Bound::positive).value_or(1.0);
    return monodisperse(1, initial.density);
  }
  if (kind == "table") {
    table->allow_only({"kind", "n"});
    initial.kind = InitialCondition::Kind::table;
    return table->numbers("n", Bound::any);  // n_1, n_2, ...; zeros beyond; checked by the model
  }
  table->fail("kind", "\"monodisperse\" or \"table\"");
}

}  // namespace

std::string model_key(const std::string& parameter) { return "model." + parameter; }

void read_model(const SceneTable& model, Scene& scene) {
  model.allow_only({"kernel", "lambda", "size", "truncation", "initial", "grid"});
  AggregationModel& m = scene.model;
  m.kernel = read_kernel(model);
  m.lambda = read_shattering_rate(model);
  m.grid = read_grid(model);
  m.size = model.count("size", 2);
  if (m.size > m.grid.largest_size())
    model.fail("size", "2 <= N <= " + std::to_string(m.grid.largest_size()) + " on the grid " + m.grid.describe());
  if (const auto truncation = model.optional_string("truncation"))
    m.truncation = under_key(model_key, [&] { return truncation_from_name(*truncation); });
  m.initial = read_initial(model, scene.initial);
  // λ(t) >= 0 on [0, end], initial densities finite and >= 0 with mass > 0
  under_key(model_key, [&] { m.validate(scene.time.end); });
}

}  // namespace aggkit
