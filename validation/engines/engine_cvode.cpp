// Engine "cvode": the truncated rate equations integrated by SUNDIALS CVODE (solvers/cvode_integrator.hpp).
// Its options are the table below (`aggkit run --help` prints it).
#include <optional>

#include "particle/common/checkpoint.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/discretisation.hpp"
#include "validation/engines/engine.hpp"
#include "analysis/input_error.hpp"
#include "validation/io/machine.hpp"
#include "validation/io/text.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

const OptionTable& cvode_options() {
  static const OptionTable table = option_table(integrator_option_rows());
  return table;
}

class CvodeEngine final : public Engine {
 public:
  CvodeEngine(std::string label, IntegratorOptions options, std::function<std::string(const std::string&)> keys)
      : Engine("cvode", std::move(label), integrator_option_rows().values(options)), options_(options), keys_(std::move(keys)) {}

  std::string describe() const override {
    return to_string(options_.method) + ", rhs " + to_string(options_.rates) + ", rtol " + shortest_text(options_.rtol) +
           ", atol " + shortest_text(options_.effective_atol()) + "/k^" + shortest_text(options_.atol_exponent);
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    try {
      return under_key(keys_, [&] { return run_solver(scene, observer); });
    } catch (const CheckpointError& e) {
      throw InputError("--resume", label(), std::string("a checkpoint this engine can continue from; ") + e.what());
    }
  }

 private:
  EngineStatistics run_solver(const Scene& scene, const EngineObserver& observer) const {
    IntegratorOptions options = options_;
    options.progress = observer.progress;
    const std::unique_ptr<Discretisation> grid = make_discretisation(scene.model);
    const std::vector<double> sizes = grid->output_sizes();
    // Checkpoints: after output k, the number of outputs done, the time, the densities and the leaked mass.
    // A resume continues from them with the scene's settings (restart in cvode_integrator.hpp: within the
    // integration tolerance of the uninterrupted run).
    std::optional<IntegratorRestart> restart;
    std::uint64_t done = 0;
    if (observer.checkpoint && !observer.checkpoint->resumed().empty()) {
      StateReader in(observer.checkpoint->resumed());
      restart.emplace();
      in.get(done);
      in.get(restart->time);
      in.get(restart->densities);
      in.get(restart->leaked_mass);
      in.expect_end();
      if (done > scene.time.outputs.size() || restart->densities.size() != scene.model.unknowns() ||
          (done > 0 && restart->time != scene.time.outputs[done - 1]))
        throw CheckpointError("the checkpoint's state does not fit this scene's outputs and sizes");
    }
    const IntegratorStatistics s = integrate(
        scene.model, scene.time.outputs, options,
        [&](double t, std::span<const double> n, double leaked) {
          observer.output(t, DensityState(n, leaked, sizes, sizes.empty() ? nullptr : grid.get()));
          ++done;
          if (observer.checkpoint && observer.checkpoint->due()) {
            StateWriter out;
            out.put(done);
            out.put(t);
            out.put(std::vector<double>(n.begin(), n.end()));
            out.put(leaked);
            observer.checkpoint->save(out.take());
          }
        },
        restart ? &*restart : nullptr);
    // Tolerance-level negative values (|n_k| < atol_k, e.g. the far tail at early times) are expected and
    // not reported; beyond the tolerance they mean an error larger than requested.
    if (s.negative_beyond_tolerance > 0 && observer.warning)
      observer.warning(std::to_string(s.negative_beyond_tolerance) +
                       " densities below -atol_k at one output; the most negative n_k = " +
                       shortest_text(s.most_negative_beyond_tolerance) + " at k = " + std::to_string(s.most_negative_size) +
                       ", t = " + shortest_text(s.most_negative_time) +
                       (sizes.empty() || scene.model.grid.scheme == GridScheme::fixed_pivot
                            ? " (tighten rtol or atol)"
                            : " (tighten rtol or atol; on a graded grid, shares that keep x² undershoot at a steep front: "
                              "a smaller grid.ratio, or grid.scheme = \"fixed-pivot\", keeps n_k >= 0)"));
    EngineStatistics statistics = statistics_of(s);
    // A resume: the output time it continued from (the statistics above count the steps since then).
    if (restart) statistics.push_back({"resumed_at", restart->time});
    return statistics;
  }

  // The options it ran with and the integrator's counters, for summary.json.
  EngineStatistics statistics_of(const IntegratorStatistics& s) const {
    return EngineStatistics{
        {"method", to_string(options_.method)},
        {"rhs", to_string(options_.rates)},
        {"preconditioner", to_string(options_.preconditioner)},
        {"rtol", options_.rtol},
        {"atol", options_.effective_atol()},
        {"atol_exponent", options_.atol_exponent},
        {"atol_floor", s.atol_floor},
        {"atol_mass", options_.atol_mass},
        {"steps", std::int64_t(s.steps)},
        {"rhs_evaluations", std::int64_t(s.rhs_evaluations)},
        {"linear_iterations", std::int64_t(s.linear_iterations)},
        {"jacobian_vector_products", std::int64_t(s.jacobian_vector_products)},
        {"jacobian_evaluations", std::int64_t(s.jacobian_evaluations)},
        {"preconditioner_setups", std::int64_t(s.preconditioner_setups)},
        {"preconditioner_solves", std::int64_t(s.preconditioner_solves)},
        {"error_test_failures", std::int64_t(s.error_test_failures)},
        {"nonlinear_failures", std::int64_t(s.nonlinear_failures)},
        {"linear_convergence_failures", std::int64_t(s.linear_convergence_failures)},
        {"integrator_wall_seconds", s.wall_seconds},
        {"kernel_rank", std::int64_t(s.kernel_rank)},
        {"kernel_relative_error", s.kernel_relative_error},
        {"active_size_final", std::int64_t(s.active_size_final)},
        {"active_size_mean", s.active_size_mean},
        {"fft_work_fraction", s.fft_work_fraction},
        {"stiff_from", s.stiff_from},
        {"negative_densities", std::int64_t(s.negative_densities)},
        {"most_negative_density", s.most_negative_density},
        {"negative_beyond_tolerance", std::int64_t(s.negative_beyond_tolerance)},
        {"most_negative_beyond_tolerance", s.most_negative_beyond_tolerance},
    };
  }

  IntegratorOptions options_;
  std::function<std::string(const std::string&)> keys_;  // solver parameter -> scene key
};

std::unique_ptr<Engine> build_cvode(const EngineOptions& given, const EngineSpec& spec, const Scene& scene) {
  // The integrator names its own parameters ("rtol"); the scene's key is "engine[i].rtol".
  const auto rekey = [&given](const std::string& parameter) { return given.key(leaf_key(parameter)); };
  IntegratorOptions options;
  given.read(integrator_option_rows(), options);
  under_key(rekey, [&] { options.validate(); });
  // The absolute tolerance atol/k^q bounds the error of M_p by about atol Σ_k k^(p-q): up to p = q + 1 that
  // is at most atol N²/2 (the sum kernel's M3 at q = 2, N = 16384 is measured to 4e-8), beyond it the far
  // tail the integrator does not control dominates (M100 of a constant-kernel run came out as -8.6e196, M10
  // at N = 4096 as 4.2e8 against 331.9), so those are refused rather than printed as if accurate.
  for (std::size_t i = 0; i < scene.observe.series.size(); ++i) {
    const Observable& o = scene.observe.series[i];
    if (o.type().form == "M<p>" && o.parameter() > options.atol_exponent + 1)
      throw InputError("observe.series[" + std::to_string(i) + "]", "\"" + o.name() + "\"",
                       "moments up to M" + shortest_text(options.atol_exponent + 1) + " for engine " + spec.label +
                           " (its absolute tolerance atol/k^q, q = atol_exponent = " + shortest_text(options.atol_exponent) +
                           ", controls M_p for p <= q + 1; raise " + given.key("atol_exponent") + " up to 6 for higher moments)");
  }
  // Measured peak memory about 480 bytes per size (constant kernel, N = 10^6: FFT work arrays, CVODE's
  // vectors and Krylov basis); the estimate takes 600.
  check_memory("model.size", std::to_string(scene.model.size), 600.0 * double(scene.model.unknowns()),
               "engine " + spec.label + ": about 600 bytes per size class");
  // integrate() refuses this too, but only when it runs: the scene must fail before any engine starts.
  if (options.method == IntegratorMethod::bdf_dense && scene.model.unknowns() > options.dense_limit)
    given.fail("method", "bdf-dense only for model.size <= " + std::to_string(options.dense_limit) +
                             " (this scene has " + std::to_string(scene.model.size) + "); use bdf-gmres");
  return std::make_unique<CvodeEngine>(spec.label, options, solver_keys(spec, cvode_options()));
}

}  // namespace

EngineType cvode_engine_type() {
  return {"cvode", "the truncated rate equations integrated by SUNDIALS CVODE", cvode_options(), need::kinetic, true, {},
          build_cvode};
}

}  // namespace aggkit
