// aggkit from a research code in C++ (built against the installed package: CMakeLists.txt beside this file).
// Two ways to get numbers, each checked against the exact solution of the constant kernel (λ = 0, unit
// monodisperse start: M0(t) = 2/(t+2)):
//  1. the integrator directly: the model in code, a callback at each output time;
//  2. the harness on a scene given as text: CVODE against the exact engine, the engines built from their
//     option tables and run into a scratch folder (series.csv, summary.json), as `aggkit run` does.
// Exits 0 when both agree with the exact solution, 1 otherwise.
#include <aggkit/analysis/moments.hpp>
#include <aggkit/solvers/cvode_integrator.hpp>
#include <aggkit/validation/harness/harness.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

int main() {
  aggkit::AggregationModel model;
  model.kernel = aggkit::Kernel::constant();
  model.size = 2048;  // the truncation N
  model.initial = aggkit::monodisperse(model.size);
  const double times[] = {1.0, 10.0};
  double worst = 0.0;
  aggkit::integrate(model, times, {}, [&](double t, std::span<const double> n, double /*leaked mass*/) {
    worst = std::max(worst, aggkit::relative_error(aggkit::moment(n, 0.0), 2.0 / (t + 2.0)));
  });
  std::printf("smoluchowski: integrator: max relative error of M0 = %.3e\n", worst);

  const aggkit::Scene scene = aggkit::parse_scene(
      "name = \"example\"\n[model]\nkernel = { name = \"constant\" }\nsize = 512\n[time]\nend = 2.0\n"
      "[[engine]]\nname = \"cvode\"\nrtol = 1e-9\n[[engine]]\nname = \"exact\"\n"
      "[observe]\nseries = [\"M0\", \"M2\"]\n[compare]\nreference = \"exact\"\ntolerance = { M0 = 1e-6, M2 = 1e-6 }\n");
  aggkit::RunOptions options;
  options.out = std::filesystem::temp_directory_path() / "aggkit-example-run";
  std::filesystem::remove_all(options.out);
  options.plot = false;
  options.report = nullptr;
  options.progress = nullptr;
  const aggkit::RunResult result = aggkit::run_scene(scene, options);
  std::printf("smoluchowski: harness: exit code %d, %zu comparisons\n", result.exit_code, result.comparisons.size());
  return worst < 1e-6 && result.exit_code == 0 && result.comparisons.size() == 2 ? 0 : 1;
}
