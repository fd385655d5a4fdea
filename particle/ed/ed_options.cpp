// The options of the event-driven engine [Degond2024], bound to EdSettings.
#include "particle/ed/ed_options.hpp"

namespace aggkit {

const OptionRows<EdSettings>& ed_option_rows() {
  using S = EdSettings;
  using B = Bind<S>;
  static const OptionRows<S> rows{{
      B::integer("cells", &S::cells, closed(0, 4294967295.0), "wanted number of broad-phase cells (0: about one per particle)"),
      B::integer("thermalize", &S::thermalize, closed(0, 1e9),
                 "elastic collisions per particle before sticking (collisions = \"elastic\": before the clock starts)",
                 "particles.thermalize or 0"),
      B::word("collisions", &S::elastic, std::vector<std::pair<std::string, bool>>{{"sticking", false}, {"elastic", true}},
              "sticking: aggregation; elastic: a hard-sphere gas (no clusters form; collision and virial observables)"),
  }};
  return rows;
}

void EdSettings::validate() const { ed_option_rows().check(*this); }

}  // namespace aggkit
