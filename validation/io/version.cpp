#include "validation/io/version.hpp"

#ifndef AGGKIT_VERSION
#define AGGKIT_VERSION "unknown"
#endif

namespace aggkit {
const char* version() { return AGGKIT_VERSION; }
}  // namespace aggkit
