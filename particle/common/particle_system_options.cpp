// The scalar keys of [particles], bound to ParticleSystem (particle_system.hpp).
#include "particle/common/particle_system.hpp"

namespace aggkit {

const OptionRows<ParticleSystem>& particle_system_option_rows() {
  using S = ParticleSystem;
  using B = Bind<S>;
  static const OptionRows<S> rows{{
      B::integer("thermalize", &S::thermalize, at_least(0), "elastic collisions per particle before sticking (an ED setting)"),
      B::integer("seed", &S::seed, at_least(0), "realization r runs on the seed mixed with r (every seed + r in a sweep)"),
      B::integer("realizations", &S::realizations, at_least(1),
                 "independent runs (different velocities, and radii, masses and cloud positions where those are random)"),
  }};
  return rows;
}

}  // namespace aggkit
