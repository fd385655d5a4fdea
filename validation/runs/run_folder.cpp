#include "validation/runs/run_folder.hpp"

#include <fstream>
#include <system_error>
#include <unistd.h>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

constexpr const char* probe_prefix = ".aggkit-write-test-";

[[noreturn]] void unusable(const std::filesystem::path& out, const std::string& why) {
  throw InputError("--out", out.string(), "a folder that can be created and written (" + why + ")");
}

}  // namespace

void check_writable_folder(const std::filesystem::path& folder, const std::filesystem::path& out, const std::string& tag) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) unusable(out, error.message());
  if (!std::filesystem::is_directory(folder, error)) unusable(out, "it is not a folder");
  const std::filesystem::path probe =
      folder / (std::string(probe_prefix) + std::to_string(::getpid()) + (tag.empty() ? "" : "-" + tag));
  std::ofstream file(probe);
  file << "probe\n";
  file.close();
  const bool written = static_cast<bool>(file);
  std::filesystem::remove(probe, error);
  if (!written) unusable(out, "cannot write files in it");
}

bool is_write_probe(const std::string& name) { return name.rfind(probe_prefix, 0) == 0; }

}  // namespace aggkit
