#include "validation/io/atomic_file.hpp"

#include <stdexcept>
#include <system_error>

namespace aggkit {

AtomicFile::AtomicFile(std::filesystem::path target)
    : target_(std::move(target)), temporary_(target_.string() + ".partial") {}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (stream_.is_open()) stream_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

std::ostream& AtomicFile::stream() {
  if (!stream_.is_open()) {
    stream_.open(temporary_, std::ios::binary | std::ios::trunc);
    if (!stream_) throw std::runtime_error("cannot write " + temporary_.string());
  }
  return stream_;
}

void AtomicFile::commit() {
  if (stream_.is_open()) {
    stream_.close();
    if (!stream_) throw std::runtime_error("writing " + temporary_.string() + " failed");
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(temporary_, error))
    throw std::runtime_error(temporary_.string() + " was not written");
  std::filesystem::rename(temporary_, target_, error);
  if (error) throw std::runtime_error("cannot rename " + temporary_.string() + " to " + target_.string() + ": " + error.message());
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& target, std::string_view contents) {
  AtomicFile file(target);
  file.stream().write(contents.data(), std::streamsize(contents.size()));
  file.commit();
}

}  // namespace aggkit
