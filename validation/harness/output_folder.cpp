#include "validation/harness/output_folder.hpp"

#include <fstream>
#include <system_error>

#include "analysis/input_error.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/runs/run_folder.hpp"

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

bool OutputFolder::marked() const {
  std::error_code error;
  return std::filesystem::is_regular_file(mark_file(), error);
}

std::vector<std::filesystem::path> OutputFolder::marked_files() const {
  std::vector<std::filesystem::path> files;
  std::ifstream in(mark_file());
  for (std::string line; std::getline(in, line);) {
    const std::filesystem::path relative = std::filesystem::path(line).lexically_normal();
    // Only plain relative paths inside the folder: a hand-edited mark must not reach outside it.
    if (line.empty() || relative.is_absolute() || relative.empty() || *relative.begin() == "..") continue;
    files.push_back(root_ / relative);
  }
  return files;
}

void OutputFolder::forget_summary() const {
  if (marked()) remove_stale(summary_file());
}

void OutputFolder::mark(const std::vector<std::string>& labels) const {
  std::string text;
  for (const auto& file : {summary_file(), report_file()})
    if (std::filesystem::exists(file)) text += file.filename().string() + "\n";
  for (const std::string& label : labels) {
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(engine_folder(label), error))
      if (entry.is_regular_file()) text += label + "/" + entry.path().filename().string() + "\n";
  }
  write_file_atomically(mark_file(), text);
}

void OutputFolder::prepare(const std::vector<std::pair<std::string, std::vector<std::string>>>& engines, bool force) const {
  std::error_code error;
  if (std::filesystem::is_directory(root_, error) && !marked() && !force) {
    // A write probe left by a run killed right after it created the folder is aggkit's own: removed, not
    // counted (otherwise the rerun of that run would refuse its own folder).
    std::size_t entries = 0;
    std::vector<std::filesystem::path> probes;
    for (const auto& entry : std::filesystem::directory_iterator(root_, error))
      if (is_write_probe(entry.path().filename().string())) probes.push_back(entry.path());
      else ++entries;
    for (const auto& probe : probes) std::filesystem::remove(probe, error);
    if (entries > 0)
      throw InputError("--out", root_.string(),
                       "an empty or new folder, or one an earlier aggkit run wrote (it holds .aggkit-outputs); this one "
                       "holds " + std::to_string(entries) + " entries aggkit did not write: choose another folder, or "
                       "add --force to write into it");
  }
  check_writable_folder(root_, root_);

  remove_stale(summary_file());  // first: a summary.json must never describe outputs of another run
  remove_stale(report_file());
  std::vector<std::filesystem::path> folders;
  for (const auto& file : marked_files()) {  // everything the previous run wrote
    remove_stale(file);
    if (file.parent_path() != root_) folders.push_back(file.parent_path());
  }
  for (const auto& folder : folders) std::filesystem::remove(folder, error);  // only if empty: never fails
  for (const auto& [label, files] : engines) {
    const auto folder = engine_folder(label);
    std::filesystem::create_directories(folder, error);
    if (error) unusable(folder, error.message());
    remove_stale(series_file(label));
    remove_stale(distribution_file(label));
    for (const std::string& name : files) remove_stale(folder / name);
  }
  // Marked before anything runs, with every file this run may write: a run that stops half-way leaves a
  // folder aggkit recognises and cleans on the next run.
  std::string text = "summary.json\nreport.png\n";
  for (const auto& [label, files] : engines) {
    text += label + "/series.csv\n" + label + "/distribution.csv\n";
    for (const std::string& name : files) text += label + "/" + name + "\n";
  }
  write_file_atomically(mark_file(), text);
}

}  // namespace aggkit
