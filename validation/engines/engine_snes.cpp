// Engine "snes": the steady state of the truncated rate equations by PETSc SNES Newton–Krylov
// (solvers/steady_state.hpp). A steady-state engine in a time-series harness: the stationary solution
// is the state at every output time (so `compare` against a time-dependent engine is meaningful when
// the scene's output times lie in the relaxed regime), DIR/<label>/distribution.csv holds it (columns
// k,n), and summary.json gets the scene's series observables evaluated on it ("steady_<name>") with
// Newton/GMRES counts and the final relative residual.
// Options: tolerance (relative residual, default 1e-10), max_newton_iterations, rhs (fast | direct),
// start_time (CVODE start), precondition (bool).
#include <sstream>

#include "analysis/input_error.hpp"
#include "solvers/steady_state.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/observables/observable.hpp"
#include "validation/scene/scene.hpp"
#include "validation/scene/scene_table.hpp"
#include "validation/observables/system_state.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

class SnesEngine final : public Engine {
 public:
  SnesEngine(std::string label, SteadyStateOptions options) : Engine("snes", std::move(label)), options_(options) {}

  std::string describe() const override {
    return "Newton-Krylov (PETSc SNES), rhs " + to_string(options_.rates) + ", tolerance " +
           shortest_text(options_.relative_tolerance);
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    const SteadyStateResult r = solve_steady_state(scene.model, options_);
    if (!r.converged) throw std::runtime_error("no steady state: " + r.note);
    std::ostringstream csv;
    csv.precision(17);
    csv << "k,n\n";
    for (std::size_t k = 0; k < r.n.size(); ++k) csv << k + 1 << ',' << r.n[k] << '\n';
    write_file_atomically(observer.folder / "distribution.csv", csv.str());
    const DensityState state(r.n, 0.0);
    for (double t : scene.time.outputs) observer.output(t, state);
    EngineStatistics statistics{
        {"newton_iterations", std::int64_t(r.newton_iterations)},
        {"krylov_iterations", std::int64_t(r.krylov_iterations)},
        {"relative_residual", r.relative_residual},
        {"leak_rate", r.leak_rate},
        {"start_time", r.start_time},
        {"solver_seconds", r.seconds},
    };
    for (const Observable& observable : scene.observe.series)
      statistics.push_back({"steady_" + observable.name(), observable.evaluate(state)});
    return statistics;
  }

 private:
  SteadyStateOptions options_;
};

std::unique_ptr<Engine> parse_snes(const SceneTable& table, std::string label, const Scene& scene) {
  const auto rekey = [&table](const std::string& library_key) { return table.key(leaf_key(library_key)); };
  SteadyStateOptions options;
  options.relative_tolerance = table.optional_number("tolerance", Bound::any).value_or(options.relative_tolerance);
  if (const auto iterations = table.optional_count("max_newton_iterations", 1)) {
    if (*iterations > 10000) table.fail("max_newton_iterations", "an integer in 1..10000");
    options.max_newton_iterations = int(*iterations);
  }
  if (const auto rhs = table.optional_string("rhs"))
    options.rates = under_key(rekey, [&] { return rates_path_from_name(*rhs); });
  options.start_time = table.optional_number("start_time", Bound::any).value_or(options.start_time);
  options.precondition = table.optional_boolean("precondition").value_or(options.precondition);
  under_key(rekey, [&] { options.validate(); });
  if (!scene.model.lambda.is_constant())
    throw InputError("model.lambda", scene.model.lambda.describe(), "a constant shattering rate for engine snes");
  return std::make_unique<SnesEngine>(std::move(label), options);
}

}  // namespace

EngineType snes_engine_type() {
  return {"snes",
          "the steady state of the truncated rate equations by PETSc SNES Newton-Krylov",
          {"tolerance", "max_newton_iterations", "rhs", "start_time", "precondition"},
          parse_snes};
}

}  // namespace aggkit
