#include "particle/common/checkpoint.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <fcntl.h>
#include <fstream>
#include <iterator>
#include <sstream>
#include <unistd.h>

namespace aggkit {

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

void StateWriter::put(const std::vector<bool>& values) {
  put(std::uint64_t(values.size()));
  for (bool b : values) put(std::uint8_t(b));
}

void StateReader::get(std::vector<bool>& values) {
  const std::uint64_t n = length(1);
  values.assign(n, false);
  for (std::uint64_t i = 0; i < n; ++i) values[i] = read<std::uint8_t>() != 0;
}

const char* StateReader::take(std::uint64_t n) {
  if (n > bytes_.size() - position_)
    throw CheckpointError("the checkpoint's state ends early (" + std::to_string(n) + " bytes wanted at byte " +
                          std::to_string(position_) + " of " + std::to_string(bytes_.size()) + ")");
  const char* at = bytes_.data() + position_;
  position_ += n;
  return at;
}

std::uint64_t StateReader::length(std::size_t element_bytes) {
  const auto n = read<std::uint64_t>();
  if (n > (bytes_.size() - position_) / element_bytes)
    throw CheckpointError("the checkpoint's state holds a length (" + std::to_string(n) + ") beyond its end");
  return n;
}

void StateReader::expect_end() const {
  if (!at_end())
    throw CheckpointError("the checkpoint's state has " + std::to_string(bytes_.size() - position_) +
                          " bytes more than this engine reads");
}

namespace {

constexpr std::array<char, 8> magic{'A', 'G', 'G', 'K', 'I', 'T', 'C', 'K'};

std::string hex(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

void write_all(int fd, const char* data, std::size_t size, const std::filesystem::path& path) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw CheckpointError("cannot write " + path.string() + ": " + std::strerror(errno));
    data += n;
    size -= std::size_t(n);
  }
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const CheckpointHeader& header, std::string_view payload) {
  StateWriter head;
  head.put(magic);
  head.put(checkpoint_format_version);
  head.put(header.aggkit_version);
  head.put(header.engine);
  head.put(header.scene_fingerprint);
  head.put(std::uint64_t(payload.size()));
  head.put(fnv1a64(payload));

  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::filesystem::path temporary = path.string() + ".partial";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("cannot create " + temporary.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, head.bytes().data(), head.bytes().size(), temporary);
    write_all(fd, payload.data(), payload.size(), temporary);
    if (::fsync(fd) != 0) throw CheckpointError("cannot sync " + temporary.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::close(fd) != 0) throw CheckpointError("cannot close " + temporary.string() + ": " + std::strerror(errno));
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    throw CheckpointError("cannot rename " + temporary.string() + " to " + path.string() + ": " + std::strerror(error));
  }
  // The rename itself is durable once the folder's entry is.
  if (const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

std::string read_checkpoint(const std::filesystem::path& path, const CheckpointHeader& expected) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("no checkpoint at " + path.string());
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string where = path.string() + ": ";
  StateReader reader(file);
  try {
    if (reader.remaining() < sizeof magic || reader.read<std::array<char, 8>>() != magic) throw CheckpointError("not an aggkit checkpoint");
    if (const auto format = reader.read<std::uint32_t>(); format != checkpoint_format_version)
      throw CheckpointError("checkpoint format " + std::to_string(format) + ", this aggkit reads format " +
                            std::to_string(checkpoint_format_version));
    const auto version = reader.read<std::string>();
    if (version != expected.aggkit_version)
      throw CheckpointError("written by aggkit " + version + ", this is aggkit " + expected.aggkit_version +
                            " (a continuation is exact only with the same program)");
    const auto engine = reader.read<std::string>();
    if (engine != expected.engine)
      throw CheckpointError("the checkpoint of engine " + engine + ", this run's engine is " + expected.engine);
    if (const auto fingerprint = reader.read<std::uint64_t>(); fingerprint != expected.scene_fingerprint)
      throw CheckpointError("written for a scene of fingerprint " + hex(fingerprint) + ", the scene now has " +
                            hex(expected.scene_fingerprint) + " (the scene changed since the checkpoint)");
    const auto length = reader.read<std::uint64_t>();
    const auto checksum = reader.read<std::uint64_t>();
    const std::uint64_t present = reader.remaining();  // the bytes after the header
    if (present != length)
      throw CheckpointError("the payload has " + std::to_string(present) + " bytes, its header says " +
                            std::to_string(length) + " (a truncated or damaged file)");
    const std::string_view payload(file.data() + (file.size() - present), present);
    if (fnv1a64(payload) != checksum)
      throw CheckpointError("the payload's checksum " + hex(fnv1a64(payload)) + " differs from the header's " + hex(checksum) +
                            " (a damaged file)");
    return std::string(payload);
  } catch (const CheckpointError& e) {
    throw CheckpointError(where + e.what());
  }
}

}  // namespace aggkit
