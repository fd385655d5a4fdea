// Links the installed aggkit and checks numbers two ways a research code would get them:
//  1. the integrator directly: constant kernel, λ = 0, M0(t) = 2/(t+2);
//  2. the harness on a scene given as text: CVODE against the exact solution, with the engines built from
//     their option tables and a run into a scratch folder.
#include <aggkit/analysis/moments.hpp>
#include <aggkit/solvers/cvode_integrator.hpp>
#include <aggkit/validation/harness/harness.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

int main() {
  aggkit::AggregationModel model;
  model.kernel = aggkit::Kernel::constant();
  model.size = 2048;
  model.initial = aggkit::monodisperse(model.size);
  const double times[] = {1.0, 10.0};
  double worst = 0.0;
  aggkit::integrate(model, times, {}, [&](double t, std::span<const double> n, double) {
    worst = std::max(worst, aggkit::relative_error(aggkit::moment(n, 0.0), 2.0 / (t + 2.0)));
  });
  std::printf("consumer: max relative error of M0 = %.3e\n", worst);

  const aggkit::Scene scene = aggkit::parse_scene(
      "name = \"consumer\"\n[model]\nkernel = { name = \"constant\" }\nsize = 512\n[time]\nend = 2.0\n"
      "[[engine]]\nname = \"cvode\"\nrtol = 1e-9\n[[engine]]\nname = \"exact\"\n"
      "[observe]\nseries = [\"M0\", \"M2\"]\n[compare]\nreference = \"exact\"\ntolerance = { M0 = 1e-6, M2 = 1e-6 }\n");
  aggkit::RunOptions options;
  options.out = std::filesystem::temp_directory_path() / "aggkit-consumer-run";
  std::filesystem::remove_all(options.out);
  options.plot = false;
  options.report = nullptr;
  options.progress = nullptr;
  const aggkit::RunResult result = aggkit::run_scene(scene, options);
  std::printf("consumer: harness run exit code %d, %zu comparisons\n", result.exit_code, result.comparisons.size());
  return worst < 1e-6 && result.exit_code == 0 && result.comparisons.size() == 2 ? 0 : 1;
}
