// Engine "exact": the closed-form solutions of pure aggregation from a unit monodisperse start
// (solvers/exact_solutions.hpp) for the constant, sum and product kernels. Moments are those of the
// untruncated system, so a comparison against it measures truncation and integration error together.
#include "solvers/exact_solutions.hpp"
#include "analysis/input_error.hpp"
#include "validation/engines/engine.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

class ExactState final : public ObservedState {
 public:
  ExactState(const std::string& kernel, std::size_t N, double t) : kernel_(kernel), size_(N), t_(t) {}
  double moment(double p) const override { return exact_moment(kernel_, p, t_); }
  double density(std::size_t k) const override { return exact_density(kernel_, k, t_); }
  double leaked_mass() const override { return 0.0; }  // nothing leaves the untruncated system
  std::vector<double> distribution() const override { return exact_distribution(kernel_, size_, t_); }

 private:
  const std::string& kernel_;
  std::size_t size_;
  double t_;
};

class ExactEngine final : public Engine {
 public:
  explicit ExactEngine(std::string label) : Engine("exact", std::move(label), nlohmann::json::object()) {}
  std::string describe() const override { return "closed-form solution of the untruncated system"; }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    const std::string& kernel = scene.model.kernel.name();
    for (double t : scene.time.outputs) observer.output(t, ExactState(kernel, scene.model.size, t));
    return {{"kernel", kernel}};
  }
};

std::unique_ptr<Engine> build_exact(const EngineOptions&, const EngineSpec& spec, const Scene& scene) {
  const std::string needs = "the exact engine (" + spec.key +
                            ") needs kernel constant, sum or product, lambda = 0 and a monodisperse start of "
                            "density 1 (product: time.end < 1)";
  const AggregationModel& model = scene.model;
  if (!has_exact_solution(model.kernel.name()))
    throw InputError("model.kernel.name", "\"" + model.kernel.name() + "\"", needs);
  if (!model.lambda.is_zero()) throw InputError("model.lambda", model.lambda.describe(), needs);
  if (scene.initial.kind != InitialCondition::Kind::monodisperse)
    throw InputError("model.initial.kind", "\"table\"", needs);
  if (scene.initial.density != 1.0)
    throw InputError("model.initial.density", shortest_text(scene.initial.density), needs);
  if (model.kernel.name() == "product" && !(scene.time.end < 1.0))
    throw InputError("time.end", shortest_text(scene.time.end), needs + "; the product kernel gels at t = 1");
  return std::make_unique<ExactEngine>(spec.label);
}

}  // namespace

EngineType exact_engine_type() {
  return {"exact", "closed-form solutions (constant, sum, product kernels; lambda = 0; unit monodisperse start)", {},
          need::kinetic, true, {}, build_exact};
}

}  // namespace aggkit
