// Engine "cvode": the truncated rate equations integrated by SUNDIALS CVODE (solvers/cvode_integrator.hpp).
// Options: method (bdf-gmres | bdf-dense | adams), rtol, atol, atol_exponent (atol_k = atol / k^q),
// atol_floor (lower bound of atol_k relative to the largest initial density),
// rhs (fast | direct), lowrank_tolerance, jacobian_tolerance, preconditioner (monomer | jacobi | none), krylov (Krylov
// subspace dimension, 0 = CVODE's default), max_steps, project_mass (bool).
#include <limits>

#include "solvers/cvode_integrator.hpp"
#include "validation/scene/scene.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

class CvodeEngine final : public Engine {
 public:
  CvodeEngine(std::string label, IntegratorOptions options) : Engine("cvode", std::move(label)), options_(options) {}

  std::string describe() const override {
    return to_string(options_.method) + ", rhs " + to_string(options_.rates) + ", rtol " + shortest_text(options_.rtol) +
           ", atol " + shortest_text(options_.effective_atol()) + "/k^" + shortest_text(options_.atol_exponent);
  }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    IntegratorOptions options = options_;
    options.progress = observer.progress;
    const IntegratorStatistics s =
        integrate(scene.model, scene.time.outputs, options, [&](double t, std::span<const double> n, double leaked) {
          observer.output(t, DensityState(n, leaked));
        });
    return {
        {"method", to_string(options_.method)},
        {"rhs", to_string(options_.rates)},
        {"preconditioner", to_string(options_.preconditioner)},
        {"rtol", options_.rtol},
        {"atol", options_.effective_atol()},
        {"atol_exponent", options_.atol_exponent},
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
        {"negative_densities", std::int64_t(s.negative_densities)},
        {"most_negative_density", s.most_negative_density},
    };
  }

 private:
  IntegratorOptions options_;
};

std::unique_ptr<Engine> parse_cvode(const SceneTable& table, std::string label, const Scene& scene) {
  // The integrator's messages say "engine.<option>"; the scene's key is "engine[i].<option>".
  const auto rekey = [&table](const std::string& library_key) { return table.key(leaf_key(library_key)); };
  IntegratorOptions options;
  if (const auto method = table.optional_string("method"))
    options.method = under_key(rekey, [&] { return integrator_method_from_name(*method); });
  if (const auto rhs = table.optional_string("rhs"))
    options.rates = under_key(rekey, [&] { return rates_path_from_name(*rhs); });
  options.rtol = table.optional_number("rtol", Bound::any).value_or(options.rtol);
  options.atol = table.optional_number("atol", Bound::any).value_or(options.atol);
  options.atol_exponent = table.optional_number("atol_exponent", Bound::any).value_or(options.atol_exponent);
  options.atol_floor = table.optional_number("atol_floor", Bound::any).value_or(options.atol_floor);
  options.jacobian_tolerance = table.optional_number("jacobian_tolerance", Bound::any).value_or(options.jacobian_tolerance);
  if (const auto steps = table.optional_count("max_steps", 1)) {
    if (*steps > std::size_t(std::numeric_limits<long>::max())) table.fail("max_steps", "an integer >= 1");
    options.max_steps = long(*steps);
  }
  options.lowrank_tolerance = table.optional_number("lowrank_tolerance", Bound::any).value_or(options.lowrank_tolerance);
  options.project_mass = table.optional_boolean("project_mass").value_or(options.project_mass);
  if (const auto preconditioner = table.optional_string("preconditioner"))
    options.preconditioner = under_key(rekey, [&] { return preconditioner_from_name(*preconditioner); });
  if (const auto krylov = table.optional_count("krylov", 0)) {
    if (*krylov > std::size_t(std::numeric_limits<int>::max())) table.fail("krylov", "an integer in 0..500");
    options.krylov_dimension = int(*krylov);
  }
  under_key(rekey, [&] { options.validate(); });
  // integrate() refuses this too, but only when it runs: the scene must fail before any engine starts.
  if (options.method == IntegratorMethod::bdf_dense && scene.model.size > options.dense_limit)
    table.fail("method", "bdf-dense only for model.size <= " + std::to_string(options.dense_limit) +
                             " (this scene has " + std::to_string(scene.model.size) + "); use bdf-gmres");
  return std::make_unique<CvodeEngine>(std::move(label), options);
}

}  // namespace

EngineType cvode_engine_type() {
  return {"cvode",
          "the truncated rate equations integrated by SUNDIALS CVODE",
          {"method", "rtol", "atol", "atol_exponent", "atol_floor", "rhs", "lowrank_tolerance", "jacobian_tolerance",
           "preconditioner", "krylov", "max_steps", "project_mass"},
          parse_cvode};
}

}  // namespace aggkit
