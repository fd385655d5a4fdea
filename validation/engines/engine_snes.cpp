// Engine "snes": the steady state of the truncated rate equations by PETSc SNES Newton–Krylov
// (solvers/steady_state.hpp). A steady-state engine in a time-series harness: the stationary solution
// is the state at every output time (so `compare` against a time-dependent engine is meaningful when
// the scene's output times lie in the relaxed regime), DIR/<label>/distribution.csv holds it (columns
// k,n), and summary.json gets the scene's series observables evaluated on it ("steady_<name>") with
// Newton/GMRES counts and the final relative residual.
#include <sstream>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/steady_state_options.hpp"
#include "validation/engines/engine.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/text.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

class SnesEngine final : public Engine {
 public:
  SnesEngine(std::string label, SteadyStateOptions options, std::function<std::string(const std::string&)> keys)
      : Engine("snes", std::move(label), steady_state_option_rows().values(options)), options_(options), keys_(std::move(keys)) {}

  std::string describe() const override {
    std::string line = "Newton-Krylov (PETSc SNES), rhs " + to_string(options_.rates) + ", tolerance " +
                       shortest_text(options_.relative_tolerance);
    if (!options_.petsc_options.empty()) line += ", PETSc options \"" + options_.petsc_options + "\"";
    if (!options_.command_line_petsc_options.empty())
      line += ", command-line PETSc options \"" + options_.command_line_petsc_options + "\"";
    return line;
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    return under_key(keys_, [&] { return run_solver(scene, observer); });
  }

 private:
  EngineStatistics run_solver(const Scene& scene, const EngineObserver& observer) const {
    const SteadyStateResult r = solve_steady_state(scene.model, options_);
    if (!r.unused_petsc_options.empty() && observer.warning) {
      std::string names;
      for (const std::string& o : r.unused_petsc_options) names += (names.empty() ? "" : ", ") + o;
      observer.warning("PETSc options not read by SNES, KSP or PC (misspelled, or for another solver?): " + names);
    }
    if (!r.converged) throw std::runtime_error("no steady state: " + r.note);
    std::ostringstream csv;
    csv.precision(17);
    csv << "k,n\n";
    // Each class's size and its density per unit size (the n_k themselves on the uniform grid, whose rows
    // are the integers k; a graded grid's pivots, solvers/size_grid.hpp).
    const std::unique_ptr<Discretisation> grid = make_discretisation(scene.model);
    const std::vector<double> sizes = grid->output_sizes(), density = grid->densities(r.n);
    for (std::size_t i = 0; i < r.n.size(); ++i) {
      if (sizes.empty()) csv << i + 1;
      else csv << sizes[i];
      csv << ',' << density[i] << '\n';
    }
    write_file_atomically(observer.folder / "distribution.csv", csv.str());
    const DensityState state(r.n, 0.0, sizes, sizes.empty() ? nullptr : grid.get());
    for (double t : scene.time.outputs) observer.output(t, state);
    EngineStatistics statistics{
        {"newton_iterations", std::int64_t(r.newton_iterations)},
        {"krylov_iterations", std::int64_t(r.krylov_iterations)},
        {"relative_residual", r.relative_residual},
        {"leak_rate", r.leak_rate},
        {"most_negative_density", r.most_negative_density},
        {"negative_mass_fraction", r.negative_mass_fraction},
        {"start_time", r.start_time},
        {"solver_seconds", r.seconds},
    };
    for (const Observable& observable : scene.observe.series)
      statistics.push_back({"steady_" + observable.name(), observable.value(state)});
    return statistics;
  }

  SteadyStateOptions options_;
  std::function<std::string(const std::string&)> keys_;  // solver parameter -> scene key
};

const OptionTable& snes_options() {
  static const OptionTable table = option_table(steady_state_option_rows());
  return table;
}

std::unique_ptr<Engine> build_snes(const EngineOptions& given, const EngineSpec& spec, const Scene& scene) {
  const auto rekey = [&given](const std::string& parameter) { return given.key(leaf_key(parameter)); };
  SteadyStateOptions options;
  given.read(steady_state_option_rows(), options);
  under_key(rekey, [&] { options.validate(); });
  options.command_line_petsc_options = scene.command_line_petsc_options;
  if (!scene.model.lambda.is_constant())
    throw InputError("model.lambda", scene.model.lambda.describe(), "a constant shattering rate for engine snes");
  if (scene.model.lambda.is_zero())
    throw InputError("model.lambda", "0",
                     "a shattering rate > 0 for engine snes: without shattering nothing returns mass to small sizes and "
                     "there is no steady state (all mass ends at k = N)");
  return std::make_unique<SnesEngine>(spec.label, options, solver_keys(spec, snes_options()));
}

}  // namespace

EngineType snes_engine_type() {
  return {"snes", "the steady state of the truncated rate equations by PETSc SNES Newton-Krylov", snes_options(),
          need::kinetic, true, {"distribution.csv"}, build_snes};
}

}  // namespace aggkit
