// Links the installed aggkit and checks one number: constant kernel, λ = 0, M0(t) = 2/(t+2).
#include <aggkit/solvers/cvode_integrator.hpp>
#include <aggkit/analysis/moments.hpp>

#include <cmath>
#include <cstdio>

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
  return worst < 1e-6 ? 0 : 1;
}
