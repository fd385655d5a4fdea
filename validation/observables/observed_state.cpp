#include "validation/observables/observed_state.hpp"

#include "analysis/moments.hpp"

namespace aggkit {

double ObservedState::moment(double p) const { return aggkit::moment(distribution(), p); }

double ObservedState::density(std::size_t k) const {
  const std::vector<double> n = distribution();
  return k >= 1 && k <= n.size() ? n[k - 1] : 0.0;
}

double DensityState::moment(double p) const { return aggkit::moment(n_, p); }

}  // namespace aggkit
