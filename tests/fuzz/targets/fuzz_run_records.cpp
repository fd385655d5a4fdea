// libFuzzer target: the run records read back when an interrupted run resumes — a scan point file
// (DIR/points/*.csv, validation/scan/scan_record.hpp), a sweep record (DIR/points/point<i>_r<r>.json,
// validation/sweep/sweep_record.hpp) and a validation's finished record (DIR/finished/<scene>.json,
// validation/validate/finished_record.hpp). A damaged record is not a record (nullopt: the run is done
// again); no exception and no sanitizer report may come out. A point file that parses must write back to
// the same record (parsed again, equal row), else the target aborts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "validation/scan/scan_record.hpp"
#include "validation/sweep/sweep_record.hpp"
#include "validation/validate/finished_record.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (const auto point = aggkit::parse_point_file(text)) {
    const auto again = aggkit::parse_point_file(aggkit::point_file_text(*point));
    if (!again || aggkit::scan_csv_row(*again) != aggkit::scan_csv_row(*point)) std::abort();
  }
  // The seed corpus's sweep record is point 0, realization 0 of engine.rtol = 1e-6.
  static const std::vector<nlohmann::json> seed_values{nlohmann::json(1e-6)}, values{nlohmann::json(0.5), nlohmann::json("tree")};
  (void)aggkit::parse_record_file(text, 0, 0, seed_values);
  (void)aggkit::parse_record_file(text, 3, 1, values);
  static const auto out = std::filesystem::temp_directory_path() / ("aggkit-fuzz-records-" + std::to_string(getpid()));
  static aggkit::PlannedScene scene = [] {
    aggkit::PlannedScene s;
    s.name = s.folder = "scene";
    s.fingerprint = "0123456789abcdef";
    std::filesystem::create_directories(aggkit::finished_folder(out));
    return s;
  }();
  std::ofstream(aggkit::finished_folder(out) / "scene.json", std::ios::binary).write(text.data(), std::streamsize(text.size()));
  (void)aggkit::read_finished_record(out, scene);
  return 0;
}
