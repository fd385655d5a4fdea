#pragma once
// The output folder of a run (`aggkit run SCENE --out DIR`):
//   DIR/<label>/series.csv, DIR/<label>/distribution.csv   per engine, and the files its kind declares
//                                                          (validation/engines/engine.hpp: EngineType::files)
//   DIR/report.png                                         the plot
//   DIR/summary.json                                       written last: its presence marks a finished run
//   DIR/.aggkit-outputs                                    aggkit's mark on the folder: the files the last run
//                                                          wrote, one relative path per line
// aggkit writes only into an empty folder, one it made, or one that holds its mark (else --force): a stale-file
// removal never acts in a folder of someone else's, and a rerun removes every file the previous run wrote.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace aggkit {

class OutputFolder {
 public:
  explicit OutputFolder(std::filesystem::path root) : root_(std::move(root)) {}
  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path engine_folder(const std::string& label) const { return root_ / label; }
  std::filesystem::path series_file(const std::string& label) const { return engine_folder(label) / "series.csv"; }
  std::filesystem::path distribution_file(const std::string& label) const {
    return engine_folder(label) / "distribution.csv";
  }
  std::filesystem::path report_file() const { return root_ / "report.png"; }
  std::filesystem::path summary_file() const { return root_ / "summary.json"; }
  std::filesystem::path mark_file() const { return root_ / ".aggkit-outputs"; }

  // Before anything runs: creates the folder and the engines' folders if needed and checks that files can
  // be written in it (else InputError for key `--out`), then removes the stale summary.json, report.png and
  // every file each engine could write (series.csv, distribution.csv and the files it declares), so that no
  // file of an earlier run into the same folder can pass for one of this run. `engines`: (label, declared
  // files) per engine.
  // A folder that exists, is not empty and lacks aggkit's mark is refused (InputError for `--out`) unless
  // `force`. Also removes the files listed in the mark (the previous run's), then empty engine folders.
  void prepare(const std::vector<std::pair<std::string, std::vector<std::string>>>& engines, bool force = false) const;
  // Removes summary.json if the folder holds aggkit's mark: done before a scene is even read, so that a run
  // refused for bad input leaves no summary of an earlier run that could pass for its own.
  void forget_summary() const;
  // Writes the mark: every file under the engines' folders and the run's own files that exist now.
  void mark(const std::vector<std::string>& labels) const;

 private:
  bool marked() const;
  std::vector<std::filesystem::path> marked_files() const;
  std::filesystem::path root_;
};

}  // namespace aggkit
