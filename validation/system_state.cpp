#include "validation/system_state.hpp"

#include "analysis/moments.hpp"

namespace aggkit {

double DensityState::moment(double p) const { return aggkit::moment(n_, p); }

}  // namespace aggkit
