#include "validation/observables/system_state.hpp"

#include <limits>

#include "analysis/moments.hpp"

namespace aggkit {

double SystemState::clusters() const { return std::numeric_limits<double>::quiet_NaN(); }
double SystemState::kinetic_energy() const { return std::numeric_limits<double>::quiet_NaN(); }

double DensityState::moment(double p) const { return aggkit::moment(n_, p); }

}  // namespace aggkit
