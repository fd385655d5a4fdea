#pragma once
// What the machine offers a run, for resource estimates made when a scene is checked: an input that
// cannot fit is refused (exit 2) with its estimate instead of failing in an allocation half-way.
#include <cstddef>
#include <string>

namespace aggkit {

double machine_memory_bytes();             // memory available now (MemAvailable), else physical; +inf if unknown
std::string memory_text(double bytes);     // "1.2 GiB"
// Throws InputError for `key` = `value` if `bytes` exceeds 80 % of the machine's memory; `what` says how
// the estimate was made ("about 2.5 kB per particle").
void check_memory(const std::string& key, const std::string& value, double bytes, const std::string& what);

}  // namespace aggkit
