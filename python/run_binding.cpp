// Engines and scenes from Python. A call builds a scene (TOML text written by python/aggkit/_scene.py from
// keyword arguments, so every value is checked as in a scene file, with the same messages), runs one engine
// with the GIL released and returns what the harness records: the series (means and standard errors), the
// size distributions, the statistics, a particle engine's final values and final configuration.
#include <pybind11/functional.h>
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <complex>
#include <chrono>
#include <filesystem>
#include <thread>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <unistd.h>

#include "analysis/input_error.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "solvers/kernels.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/size_grid.hpp"
#include "solvers/stability.hpp"
#include "validation/engines/engine.hpp"
#include "validation/harness/engine_record.hpp"
#include "validation/harness/harness.hpp"
#include "validation/harness/recording_observer.hpp"
#include "validation/harness/run_checkpoint.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/text.hpp"
#include "validation/runs/fingerprint.hpp"

namespace py = pybind11;
using namespace aggkit;

namespace {

// A numpy array that owns its buffer (no copy on the way out).
py::array_t<double> owned_array(std::vector<double>&& values, std::vector<py::ssize_t> shape) {
  auto* buffer = new std::vector<double>(std::move(values));
  py::capsule owner(buffer, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>(shape, buffer->data(), owner);
}

// Raised from inside an engine when the caller pressed Ctrl-C; turned into KeyboardInterrupt with the GIL.
struct Interrupted {};

// Checks for Ctrl-C and calls the user's progress callback, at most every 0.1 s, from the calling thread only
// (Python handles signals on the main thread).
class Watcher {
 public:
  explicit Watcher(py::object progress) : progress_(std::move(progress)), caller_(std::this_thread::get_id()) {}
  void tick(const std::string& what) {
    if (std::this_thread::get_id() != caller_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      interrupted_ = true;
      throw Interrupted{};
    }
    if (!progress_.is_none()) progress_(what);
  }
  bool interrupted() const { return interrupted_; }

 private:
  py::object progress_;
  std::thread::id caller_;
  std::chrono::steady_clock::time_point last_{};
  bool interrupted_ = false;
};

// A scratch folder for the files an engine writes besides what it reports (final.json, snapshots).
struct ScratchFolder {
  std::filesystem::path path;
  ScratchFolder() {
    static std::atomic<int> counter{0};
    path = std::filesystem::temp_directory_path() /
           ("aggkit-python-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(path);
  }
  ~ScratchFolder() {
    std::error_code error;
    std::filesystem::remove_all(path, error);
  }
};

struct FinalConfiguration {
  std::vector<double> positions, velocities, masses;
  std::vector<std::uint32_t> cluster;
  std::vector<double> radii;  // each particle's
  int dimension = 0;
  std::array<double, 3> box{};
  bool periodic = false;
};

// A scene's text with what Python gives beyond it: a callable λ(t), a callable kernel K(i, j), an initial
// table (each checked as the scene's own would be).
Scene python_scene(const std::string& scene_text, py::object kernel, py::object initial, py::object lambda) {
  Scene scene = parse_scene(scene_text, "arguments");
  if (!lambda.is_none()) {
    // λ(t) from Python: called with the GIL at every evaluation of the rates.
    py::function f = lambda.cast<py::function>();
    scene.model.lambda = ShatteringRate::function(
        [f](double t) {
          py::gil_scoped_acquire gil;
          return f(t).cast<double>();
        },
        "callable");
    scene.model.lambda.validate(scene.time.end, "lam");
  }
  if (!kernel.is_none()) {
    // A Python kernel K(i, j): called with the GIL, pair by pair (the kernel's factorisation samples it).
    py::function k = kernel.cast<py::function>();
    scene.model.kernel = Kernel::user("python", [k](double i, double j) {
      py::gil_scoped_acquire gil;
      const double value = k(i, j).cast<double>();
      if (!(value >= 0) || !std::isfinite(value))
        throw InputError("kernel", shortest_text(value) + " at (" + shortest_text(i) + ", " + shortest_text(j) + ")",
                         "a finite kernel value >= 0");
      return value;
    });
  }
  if (!initial.is_none()) {
    const auto n = initial.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (n.ndim() != 1 || std::size_t(n.shape(0)) > scene.model.size)
      throw InputError("initial", std::to_string(n.size()) + " entries",
                       "a 1-D array of at most size = " + std::to_string(scene.model.size) + " densities");
    // Zeros beyond the table (solvers/model.hpp): a graded grid's N may be far too large to pad to.
    scene.model.initial.assign(std::size_t(n.shape(0)), 0.0);
    std::copy(n.data(), n.data() + n.shape(0), scene.model.initial.begin());
    scene.model.validate(scene.time.end);  // keys as the Python arguments name them ("initial.n[3]")
  }
  return scene;
}

// What run_engine returns: the record's series (means, standard errors), distributions, the statistics,
// final values, warnings and the final configuration of the first realization.
py::dict result_dict(const Scene& scene, const EngineRecord& record, const EngineStatistics& statistics,
                     std::optional<FinalConfiguration>& configuration) {
  py::dict out;
  const auto T = py::ssize_t(record.times.size());
  out["t"] = owned_array(std::vector<double>(record.times), {T});
  py::dict series, errors;
  for (std::size_t j = 0; j < scene.observe.series.size(); ++j) {
    std::vector<double> column, error;
    for (std::size_t i = 0; i < record.times.size(); ++i) {
      column.push_back(record.values[i][j]);
      if (!record.standard_errors.empty()) error.push_back(record.standard_errors[i][j]);
    }
    series[py::str(scene.observe.series[j].name())] = owned_array(std::move(column), {T});
    if (!error.empty()) errors[py::str(scene.observe.series[j].name())] = owned_array(std::move(error), {T});
  }
  out["series"] = series;
  out["stderr"] = errors;
  if (!record.distributions.empty()) {
    std::size_t width = 0;
    for (const auto& d : record.distributions) width = std::max(width, d.n.size());
    std::vector<double> n(record.distributions.size() * width, 0.0), times;
    for (std::size_t i = 0; i < record.distributions.size(); ++i) {
      std::copy(record.distributions[i].n.begin(), record.distributions[i].n.end(), n.begin() + i * width);
      times.push_back(record.distributions[i].t);
    }
    out["n"] = owned_array(std::move(n), {py::ssize_t(record.distributions.size()), py::ssize_t(width)});
    out["n_times"] = owned_array(std::move(times), {py::ssize_t(record.distributions.size())});
    if (!record.distributions.front().sizes.empty()) {  // a graded grid: the classes' sizes (pivots)
      std::vector<double> sizes = record.distributions.front().sizes;
      const auto count = py::ssize_t(sizes.size());
      // The densities per unit size the numbers stand for (solvers/size_grid.hpp section_densities).
      std::vector<double> density(record.distributions.size() * width, 0.0);
      for (std::size_t i = 0; i < record.distributions.size(); ++i) {
        const DistributionRecord& d = record.distributions[i];
        const std::vector<double> f = section_densities(sizes, d.n, scene.model.grid.scheme, scene.model.grid.resolved);
        std::copy(f.begin(), f.end(), density.begin() + std::ptrdiff_t(i * width));
      }
      out["density"] = owned_array(std::move(density), {py::ssize_t(record.distributions.size()), py::ssize_t(width)});
      out["sizes"] = owned_array(std::move(sizes), {count});
    }
  }
  py::dict stats;
  for (const auto& s : statistics) std::visit([&](const auto& v) { stats[py::str(s.name)] = v; }, s.value);
  out["statistics"] = stats;
  py::dict final_values;
  for (const auto& f : record.finals) final_values[py::str(f.name)] = py::make_tuple(f.mean, f.standard_error);
  out["final"] = final_values;
  out["engine"] = record.label;
  out["warnings"] = record.warnings;  // aggkit/__init__.py issues each as an aggkit.EngineWarning
  if (configuration) {
    const auto count = py::ssize_t(configuration->cluster.size());
    py::dict c;
    c["positions"] = owned_array(std::move(configuration->positions), {count, 3});
    c["velocities"] = owned_array(std::move(configuration->velocities), {count, 3});
    c["masses"] = owned_array(std::move(configuration->masses), {count});
    c["radii"] = owned_array(std::move(configuration->radii), {count});
    c["cluster"] = py::array_t<std::uint32_t>(count, configuration->cluster.data());
    c["dimension"] = configuration->dimension;
    c["box"] = py::make_tuple(configuration->box[0], configuration->box[1], configuration->box[2]);
    c["periodic"] = configuration->periodic;
    out["configuration"] = c;
  }
  return out;
}

py::dict run_engine(const std::string& scene_text, std::size_t engine_index, py::object kernel, py::object initial,
                    py::object lambda, py::object progress) {
  const Scene scene = python_scene(scene_text, std::move(kernel), std::move(initial), std::move(lambda));
  const std::unique_ptr<Engine> engine = build_engine(scene, engine_index);
  if (const auto every = engine->settings().find("checkpoint_every");
      every != engine->settings().end() && every->is_number() && every->get<double>() > 0)
    throw InputError("checkpoint_every", shortest_text(every->get<double>()),
                     "0 here: checkpoints need an output folder — aggkit.run(scene, out, checkpoint_every=...) or a "
                     "scene's engine option with aggkit.run(scene, out, resume=True)");

  EngineRecord record;
  record.label = engine->label();
  record.name = engine->name();
  std::mutex record_lock;
  std::optional<FinalConfiguration> configuration;
  Watcher watcher(progress);
  const ScratchFolder scratch;
  // The harness's observer (measurements, final values, warnings), with Ctrl-C and the progress callback.
  EngineObserver observer = recording_observer(scene, record, record_lock,
                                               {[&watcher](double t) { watcher.tick("t = " + shortest_text(t)); },
                                                [&watcher](const std::string& what) { watcher.tick(what); }});
  observer.final_configuration = [&](const ParticleView& view) {
    FinalConfiguration c;
    const ParticleConfiguration& config = view.configuration();
    for (const auto& x : config.positions) c.positions.insert(c.positions.end(), x.begin(), x.end());
    for (const auto& v : view.velocities()) c.velocities.insert(c.velocities.end(), v.begin(), v.end());
    c.masses.assign(view.masses().begin(), view.masses().end());
    c.cluster.assign(view.cluster_labels().begin(), view.cluster_labels().end());
    for (std::size_t i = 0; i < config.positions.size(); ++i) c.radii.push_back(config.radius_of(i));
    c.dimension = config.dimension, c.box = config.box, c.periodic = config.periodic;
    configuration = std::move(c);
  };
  observer.folder = scratch.path;
  EngineStatistics statistics;
  try {
    py::gil_scoped_release release;
    statistics = engine->run(scene, observer);
  } catch (const Interrupted&) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }

  return result_dict(scene, record, statistics, configuration);
}

// The whole harness on a scene: returns summary.json's text. `resume`: continue from the checkpoints in
// `out` if it has them (the scene's text must be the one they were written for), else start with them;
// `checkpoint_every`: wall seconds between checkpoints (0: each engine's own option).
std::string run_scene_text(const std::string& scene_text, const std::string& source, const std::string& out,
                           bool force, bool plot, bool resume, double checkpoint_every) {
  const Scene scene = parse_scene(scene_text, source);
  if ((resume || checkpoint_every > 0) && out.empty())
    throw InputError(resume ? "resume" : "checkpoint_every", resume ? "True" : shortest_text(checkpoint_every),
                     "checkpoints need an output folder: out = DIR");
  if (!(checkpoint_every >= 0) || !std::isfinite(checkpoint_every))
    throw InputError("checkpoint_every", shortest_text(checkpoint_every), "wall seconds >= 0 (0: the engines' own option)");
  const std::unique_ptr<ScratchFolder> scratch = out.empty() ? std::make_unique<ScratchFolder>() : nullptr;
  RunOptions options;
  options.out = out.empty() ? scratch->path / "run" : std::filesystem::path(out);
  options.force = force;
  options.plot = plot;
  options.scene_fingerprint = text_fingerprint(scene_text);
  if (std::filesystem::exists(source)) options.scene_file = std::filesystem::absolute(source);
  options.checkpoint_every = checkpoint_every;
  if (resume && std::filesystem::exists(options.out / "checkpoint" / "run.json")) {
    const CheckpointedRun earlier = read_checkpointed_run(options.out);
    if (earlier.fingerprint != options.scene_fingerprint)
      throw InputError("resume", "True", "a scene unchanged since the checkpoints in " + out + " were written (its text differs)");
    options.resume = true;
    if (checkpoint_every == 0) options.checkpoint_every = earlier.interval;
  }
  options.report = nullptr;
  options.progress = nullptr;
  options.warnings = nullptr;
  {
    py::gil_scoped_release release;
    run_scene(scene, options);
  }
  std::ifstream in(options.out / "summary.json");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The model of a scene's [model] section (the Python Model's), with a Python kernel if given.
AggregationModel model_of(const std::string& scene_text, py::object kernel) {
  Scene scene = parse_scene(scene_text, "arguments");
  if (!kernel.is_none()) {
    py::function k = kernel.cast<py::function>();
    scene.model.kernel = Kernel::user("python", [k](double i, double j) {
      py::gil_scoped_acquire gil;
      return k(i, j).cast<double>();
    });
  }
  return scene.model;
}

// The Hopf normal form at a steady state (solvers/hopf_normal_form.hpp) as a dict.
py::dict normal_form(const std::string& scene_text, py::object kernel,
                     const py::array_t<double, py::array::c_style | py::array::forcecast>& state) {
  const AggregationModel model = model_of(scene_text, kernel);
  if (state.ndim() != 1 || std::size_t(state.shape(0)) != model.unknowns())
    throw InputError("state", std::to_string(state.size()) + " entries",
                     "a 1-D array of one density per size class (" + std::to_string(model.unknowns()) + ")");
  const std::vector<double> n(state.data(), state.data() + state.shape(0));
  HopfNormalForm form;
  {
    py::gil_scoped_release release;
    form = hopf_normal_form(model, n);
  }
  py::dict d;
  d["mu"] = form.mu;
  d["c1"] = form.c1;
  d["lyapunov"] = form.lyapunov;
  d["supercritical"] = form.supercritical();
  d["radius"] = form.radius();
  d["frequency"] = form.frequency();
  d["m0_half_range"] = form.m0_half_range();
  d["eigen_residual"] = form.eigen_residual;
  d["q"] = py::array_t<std::complex<double>>(py::ssize_t(form.q.size()), form.q.data());
  return d;
}

py::array_t<std::complex<double>> rightmost_eigenvalues(const std::string& scene_text, py::object kernel,
                                                        const py::array_t<double, py::array::c_style | py::array::forcecast>& state,
                                                        int count) {
  const AggregationModel model = model_of(scene_text, kernel);
  if (state.ndim() != 1 || std::size_t(state.shape(0)) != model.unknowns())
    throw InputError("state", std::to_string(state.size()) + " entries",
                     "a 1-D array of one density per size class (" + std::to_string(model.unknowns()) + ")");
  if (count < 1) throw InputError("count", std::to_string(count), "an integer >= 1");
  const std::vector<double> n(state.data(), state.data() + state.shape(0));
  StabilityResult result;
  {
    py::gil_scoped_release release;
    result = analyse_stability(model, n, count);
  }
  return py::array_t<std::complex<double>>(py::ssize_t(result.rightmost.size()), result.rightmost.data());
}

// LimitCycleOptions from a dict of keywords; an unknown key is refused by name.
LimitCycleOptions cycle_options(const py::dict& given) {
  LimitCycleOptions o;
  for (const auto& [key, value] : given) {
    const std::string name = py::str(key);
    if (name == "rtol") o.rtol = value.cast<double>();
    else if (name == "tolerance") o.tolerance = value.cast<double>();
    else if (name == "max_newton_iterations") o.max_newton_iterations = value.cast<int>();
    else if (name == "linear_tolerance") o.linear_tolerance = value.cast<double>();
    else if (name == "max_krylov_iterations") o.max_krylov_iterations = value.cast<int>();
    else if (name == "floquet_count") o.floquet_count = value.cast<int>();
    else if (name == "orbit_samples") o.orbit_samples = value.cast<std::size_t>();
    else
      throw InputError(name, py::str(value), "one of rtol, tolerance, max_newton_iterations, linear_tolerance, "
                                             "max_krylov_iterations, floquet_count, orbit_samples");
  }
  o.validate();
  return o;
}

py::dict cycle_dict(const LimitCycle& c) {
  py::dict d;
  d["converged"] = c.converged, d["period"] = c.period, d["m0_min"] = c.m0_min, d["m0_max"] = c.m0_max;
  d["state"] = py::array_t<double>(py::ssize_t(c.state.size()), c.state.data());
  d["sizes"] = py::array_t<double>(py::ssize_t(c.sizes.size()), c.sizes.data());
  d["floquet"] = py::array_t<std::complex<double>>(py::ssize_t(c.floquet.size()), c.floquet.data());
  d["floquet_converged"] = c.floquet_converged, d["stable"] = c.stable;
  std::vector<double> orbit;
  for (std::size_t i = 0; i < c.orbit_time.size(); ++i) {
    orbit.push_back(c.orbit_time[i]);
    orbit.insert(orbit.end(), c.orbit_moments[i].begin(), c.orbit_moments[i].end());
  }
  d["orbit"] = py::array_t<double>({py::ssize_t(c.orbit_time.size()), py::ssize_t(5)}, orbit.data());
  d["newton_iterations"] = c.newton_iterations, d["krylov_iterations"] = c.krylov_iterations;
  d["period_maps"] = c.period_maps, d["residual"] = c.residual, d["seconds"] = c.seconds, d["note"] = c.note;
  return d;
}

// The periodic orbit from `start` (a state with `period` its period guess) or, without one, from a run of the
// model to t = settle (solvers/limit_cycle.hpp cycle_start_from_run).
py::dict limit_cycle(const std::string& scene_text, py::object kernel, py::object start, py::object period, double settle,
                     const py::dict& options) {
  const AggregationModel model = model_of(scene_text, kernel);
  const LimitCycleOptions o = cycle_options(options);
  std::vector<double> x0;
  double T = 0.0;
  if (!start.is_none()) {
    const auto n = start.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (n.ndim() != 1 || std::size_t(n.shape(0)) != model.unknowns())
      throw InputError("start", std::to_string(n.size()) + " entries",
                       "a 1-D array of one density per size class (" + std::to_string(model.unknowns()) + ")");
    if (period.is_none()) throw InputError("period", "None", "a period guess > 0 with a start");
    x0.assign(n.data(), n.data() + n.shape(0));
    T = period.cast<double>();
  }
  LimitCycle c;
  {
    py::gil_scoped_release release;
    if (x0.empty()) {
      const std::optional<CycleStart> found = cycle_start_from_run(model, settle, settle / 4000.0);
      if (!found) {
        c.note = "the run to t = " + format_value(settle) + " shows no oscillation (fewer than 3 crossings of M0's mean in its second half)";
      } else {
        x0 = found->state;
        T = period.is_none() ? found->period : period.cast<double>();
      }
    }
    if (!x0.empty()) c = find_limit_cycle(model, x0, T, o);
  }
  return cycle_dict(c);
}

py::dict hopf(const std::string& scene_text, double a, double lambda_lo, double lambda_hi, double tolerance) {
  const AggregationModel model = model_of(scene_text, py::none());
  HopfPoint h;
  {
    py::gil_scoped_release release;
    h = locate_hopf(model, a, lambda_lo, lambda_hi, tolerance);
  }
  py::dict d;
  d["a"] = h.a, d["found"] = h.found, d["lambda_crit"] = h.lambda_crit, d["lambda_tolerance"] = h.lambda_tolerance;
  d["omega"] = h.omega, d["period"] = h.omega > 0 ? 2 * M_PI / h.omega : NAN, d["note"] = h.note;
  d["evaluations"] = h.evaluations, d["seconds"] = h.seconds;
  return d;
}

// An option table as Python lists it: key, default (as text), allowed, doc and value.
py::list option_list(const OptionTable& table) {
  py::list rows;
  for (const OptionSpec& o : table) {
    py::dict row;
    row["key"] = o.key, row["default"] = o.default_text(), row["allowed"] = o.allowed(), row["doc"] = o.doc;
    // The value a run uses without the key (None: none, or computed as `default` says): the keyword's default.
    const nlohmann::json& v = o.default_note.empty() ? o.fallback : nlohmann::json();
    if (v.is_boolean()) row["value"] = v.get<bool>();
    else if (v.is_number_unsigned()) row["value"] = v.get<std::uint64_t>();
    else if (v.is_number_integer()) row["value"] = v.get<std::int64_t>();
    else if (v.is_number()) row["value"] = v.get<double>();
    else if (v.is_string()) row["value"] = v.get<std::string>();
    else row["value"] = py::none();
    rows.append(row);
  }
  return rows;
}

py::list engine_option_table(const std::string& engine) {
  const EngineType* type = find_engine_type(engine);
  if (!type) throw InputError("engine", "\"" + engine + "\"", "one of " + join(engine_names()));
  return option_list(type->options);
}

// The kernel registry (solvers/kernels.hpp): name, formula and parameters (name, allowed, default or None).
py::list kernel_list() {
  py::list kernels;
  for (const KernelEntry& entry : kernel_registry()) {
    py::list parameters;
    for (const KernelParameter& p : entry.parameters) {
      py::dict parameter;
      parameter["name"] = p.name, parameter["allowed"] = p.allowed;
      parameter["default"] = p.fallback ? py::object(py::float_(*p.fallback)) : py::object(py::none());
      parameters.append(parameter);
    }
    py::dict kernel;
    kernel["name"] = entry.name, kernel["formula"] = entry.formula, kernel["parameters"] = parameters;
    kernels.append(kernel);
  }
  return kernels;
}

}  // namespace

void bind_runs(py::module_& m) {
  m.def("run_engine", &run_engine, py::arg("scene_text"), py::arg("engine") = 0, py::arg("kernel") = py::none(),
        py::arg("initial") = py::none(), py::arg("lam") = py::none(), py::arg("progress") = py::none());
  m.def("run_scene", &run_scene_text, py::arg("scene_text"), py::arg("source"), py::arg("out"), py::arg("force"),
        py::arg("plot"), py::arg("resume") = false, py::arg("checkpoint_every") = 0.0);
  m.def("option_table", &engine_option_table, py::arg("engine"));
  m.def("engine_kinds", [] {
    py::list kinds;
    for (const EngineType& type : engine_types()) {
      py::dict kind;
      kind["name"] = type.name, kind["description"] = type.description, kind["particles"] = !type.needs_model;
      kinds.append(kind);
    }
    return kinds;
  });
  m.def("rightmost_eigenvalues", &rightmost_eigenvalues, py::arg("scene_text"), py::arg("kernel"), py::arg("state"),
        py::arg("count"));
  m.def("hopf_normal_form", &normal_form, py::arg("scene_text"), py::arg("kernel"), py::arg("state"));
  m.def("limit_cycle", &limit_cycle, py::arg("scene_text"), py::arg("kernel"), py::arg("start"), py::arg("period"),
        py::arg("settle"), py::arg("options"));
  m.def("locate_hopf", &hopf, py::arg("scene_text"), py::arg("a"), py::arg("lambda_lo"), py::arg("lambda_hi"),
        py::arg("tolerance"));
  m.def("engine_names", &engine_names);
  m.def("kernels", &kernel_list);
  m.def("grid_options", [] { return option_list(size_grid_option_rows().table()); });
}
