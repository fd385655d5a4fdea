#pragma once
// The options of the event-driven engine, bound to EdSettings (analysis/option_rows.hpp): key, range, doc
// and the field each sets. The engine's `stop` (a cluster target) is the particle runner's, not the
// physics': validation/engines/sticky_spheres.hpp.
#include <cstddef>

#include "analysis/option_rows.hpp"

namespace aggkit {

struct EdSettings {
  std::size_t cells = 0;       // wanted number of broad-phase cells (0: about one per particle)
  std::size_t thermalize = 0;  // elastic collisions per particle before sticking (elastic gas: before the clock starts)
  bool elastic = false;        // a hard-sphere gas: every collision elastic, no clusters form
  // InputError for a field outside its option row's range (ed_option_rows).
  void validate() const;
};

const OptionRows<EdSettings>& ed_option_rows();

}  // namespace aggkit
