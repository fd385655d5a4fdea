#include "validation/io/machine.hpp"

#include <cstdio>
#include <fstream>
#include <string>
#include <limits>
#include <unistd.h>

#include "analysis/input_error.hpp"

namespace aggkit {

double machine_memory_bytes() {
  // What a run can have now: MemAvailable (Linux), else the physical memory.
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    double kib = 0;
    if (key == "MemAvailable:" && meminfo >> kib) return kib * 1024.0;
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::numeric_limits<double>::infinity();
  return double(pages) * double(page);
}

std::string memory_text(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) bytes /= 1024, ++u;
  char text[64];
  std::snprintf(text, sizeof text, bytes < 10 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
  return text;
}

void check_memory(const std::string& key, const std::string& value, double bytes, const std::string& what) {
  const double available = 0.8 * machine_memory_bytes();
  if (!(bytes <= available))
    throw InputError(key, value,
                     "a size this machine can hold: the run would need about " + memory_text(bytes) + " (" + what +
                         "), more than 80 % of the " + memory_text(machine_memory_bytes()) + " of memory available");
}

}  // namespace aggkit
