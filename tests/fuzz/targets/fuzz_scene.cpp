// libFuzzer target: a scene file's text, read by the scene reader with every section ([model], [particles],
// [[engine]] options, [observe], [compare], [sweep]), then the engines built up to where a run would start,
// and the same text read as an `aggkit scan` and an `aggkit sweep` plan. Bad input must give InputError and
// nothing else: any other exception escapes and is a finding, as are the sanitizers' reports. A scene may
// name the start file "start.csv" (a valid 2-D start of 4 particles, written once beside the input).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <unistd.h>

#include "analysis/input_error.hpp"
#include "validation/engines/engine.hpp"
#include "validation/scan/scan_plan.hpp"
#include "validation/scene/scene.hpp"
#include "validation/sweep/sweep_plan.hpp"

namespace {

std::filesystem::path folder() {
  static const std::filesystem::path path = [] {
    const auto p = std::filesystem::temp_directory_path() / ("aggkit-fuzz-scene-" + std::to_string(getpid()));
    std::filesystem::create_directories(p);
    std::ofstream(p / "start.csv") << "x,y,vx,vy,radius,mass\n0,0,1,0,0.5,1\n2,0,-1,0,0.5,1\n0,2,0,1,0.5,1\n2,2,0,-1,0.5,2\n";
    return p;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const aggkit::Scene scene = aggkit::parse_scene(text, "fuzz", folder());
    (void)aggkit::build_engines(scene);
  } catch (const aggkit::InputError&) {
  }
  try {
    (void)aggkit::parse_scan_plan(text, "fuzz");
  } catch (const aggkit::InputError&) {
  }
  try {
    (void)aggkit::parse_sweep_plan(text, "fuzz");
  } catch (const aggkit::InputError&) {
  }
  return 0;
}
