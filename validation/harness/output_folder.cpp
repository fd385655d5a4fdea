#include "validation/harness/output_folder.hpp"

#include <fstream>
#include <system_error>
#include <unistd.h>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

[[noreturn]] void unusable(const std::filesystem::path& root, const std::string& why) {
  throw InputError("--out", root.string(), "a folder that can be created and written (" + why + ")");
}

void remove_stale(const std::filesystem::path& file) {
  std::error_code error;
  std::filesystem::remove(file, error);
  if (error) throw InputError("--out", file.string(), "cannot remove a stale output (" + error.message() + ")");
}

}  // namespace

void OutputFolder::prepare(const std::vector<std::pair<std::string, std::vector<std::string>>>& engines) const {
  std::error_code error;
  std::filesystem::create_directories(root_, error);
  if (error) unusable(root_, error.message());
  if (!std::filesystem::is_directory(root_, error)) unusable(root_, "it is not a folder");
  // Root may write anywhere by permissions alone; only writing a file proves the folder is usable.
  const std::filesystem::path probe = root_ / (".aggkit-write-test-" + std::to_string(::getpid()));
  {
    std::ofstream file(probe);
    file << "probe\n";
    file.close();
    if (!file) {
      std::filesystem::remove(probe, error);
      unusable(root_, "cannot write files in it");
    }
  }
  std::filesystem::remove(probe, error);

  remove_stale(summary_file());  // first: a summary.json must never describe outputs of another run
  remove_stale(report_file());
  for (const auto& [label, files] : engines) {
    const auto folder = engine_folder(label);
    std::filesystem::create_directories(folder, error);
    if (error) unusable(folder, error.message());
    remove_stale(series_file(label));
    remove_stale(distribution_file(label));
    for (const std::string& name : files) remove_stale(folder / name);
  }
}

}  // namespace aggkit
