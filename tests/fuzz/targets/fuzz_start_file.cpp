// libFuzzer target: a particle start file (`initial = { file = ... }`, particle/common/start_file.hpp), read
// as 2-D and as 3-D. Bad input must give InputError and nothing else; a start read back must be what was
// written again (write_start_file round trip), else the target aborts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "analysis/input_error.hpp"
#include "particle/common/start_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto file = std::filesystem::temp_directory_path() / ("aggkit-fuzz-start-" + std::to_string(getpid()) + ".csv");
  static const auto again = std::filesystem::temp_directory_path() / ("aggkit-fuzz-start-" + std::to_string(getpid()) + "-again.csv");
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  for (int dimension : {2, 3}) {
    try {
      const aggkit::StartFile start = aggkit::read_start_file(file, dimension);
      aggkit::write_start_file(again, dimension, start.particles);
      const aggkit::StartFile back = aggkit::read_start_file(again, dimension);
      if (back.particles.positions != start.particles.positions || back.particles.velocities != start.particles.velocities ||
          back.particles.radii != start.particles.radii || back.particles.masses != start.particles.masses)
        std::abort();
    } catch (const aggkit::InputError&) {
    }
  }
  return 0;
}
