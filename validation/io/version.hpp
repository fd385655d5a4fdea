#pragma once
namespace aggkit {
const char* version();  // the project version, e.g. "0.1.0"
}  // namespace aggkit
