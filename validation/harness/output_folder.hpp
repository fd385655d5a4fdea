#pragma once
// The output folder of a run (`aggkit run SCENE --out DIR`):
//   DIR/<label>/series.csv, DIR/<label>/distribution.csv   per engine, and the files its kind declares
//                                                          (validation/engines/engine.hpp: EngineType::files)
//   DIR/report.png                                         the plot
//   DIR/summary.json                                       written last: its presence marks a finished run
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

  // Before anything runs: creates the folder and the engines' folders if needed and checks that files can
  // be written in it (else InputError for key `--out`), then removes the stale summary.json, report.png and
  // every file each engine could write (series.csv, distribution.csv and the files it declares), so that no
  // file of an earlier run into the same folder can pass for one of this run. `engines`: (label, declared
  // files) per engine.
  void prepare(const std::vector<std::pair<std::string, std::vector<std::string>>>& engines) const;

 private:
  std::filesystem::path root_;
};

}  // namespace aggkit
