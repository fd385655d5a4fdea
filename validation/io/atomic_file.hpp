#pragma once
// A file written under a temporary name in its own folder and renamed into place when complete, so that
// a failed or interrupted run never leaves a half-written file under the final name.
#include <filesystem>
#include <fstream>
#include <string_view>

namespace aggkit {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // The stream writing the temporary file (opened on first use).
  std::ostream& stream();
  // "<folder>/<name>.partial": for a program that writes the file itself.
  const std::filesystem::path& temporary_path() const { return temporary_; }
  const std::filesystem::path& target() const { return target_; }
  // Closes the stream and renames the temporary file to the target; throws std::runtime_error if writing
  // failed or the temporary file does not exist.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Writes `contents` to `target` through an AtomicFile.
void write_file_atomically(const std::filesystem::path& target, std::string_view contents);

}  // namespace aggkit
