#pragma once
// Checkpoint files: an engine's complete state, written so that a killed run continues where it was.
//   * StateWriter / StateReader: the state as bytes, in the order it is written (numbers in this machine's
//     representation, vectors and strings with their lengths). A reader that runs past the end, or a length
//     beyond what is left, throws CheckpointError: a state is never half-read.
//   * write_checkpoint: header + payload into one file, atomically — a temporary file in the same folder,
//     fsync, rename over the target, fsync of the folder — so a kill at any moment leaves the previous
//     checkpoint or the new one, never a mixture.
//   * read_checkpoint: refuses (CheckpointError, saying why) a file that is not a checkpoint, of another
//     format version, of another aggkit version, of another engine or scene, whose payload length differs
//     from the bytes present (truncated, or grown) or whose checksum does not match.
// The header: the magic "AGGKITCK", the format version (uint32), aggkit's version, the engine (strings), the
// scene fingerprint, the payload length and the payload's FNV-1a 64-bit checksum (uint64s); then the payload.
// Checkpoints are read on the machine (byte order, word size) that wrote them.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace aggkit {

class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// FNV-1a, 64 bits: a stable digest of bytes (a scene's text, a payload); not a cryptographic hash.
std::uint64_t fnv1a64(std::string_view bytes);

class StateWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void put(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(std::uint64_t(values.size()));
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put(const std::vector<bool>& values);
  void put(std::string_view text) {
    put(std::uint64_t(text.size()));
    bytes_.append(text.data(), text.size());
  }
  void put(const std::string& text) { put(std::string_view(text)); }
  void put(const char* text) { put(std::string_view(text)); }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  explicit StateReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  void get(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
  }
  template <class T>
  void get(std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::uint64_t n = length(sizeof(T));
    values.resize(n);
    if (n > 0) std::memcpy(values.data(), take(n * sizeof(T)), n * sizeof(T));
  }
  void get(std::vector<bool>& values);
  void get(std::string& text) {
    const std::uint64_t n = length(1);
    text.assign(take(n), n);
  }
  template <class T>
  T read() {
    T value{};
    get(value);
    return value;
  }
  // A length prefix of elements that take at least `element_bytes` each in the state: CheckpointError if that
  // many cannot be in the bytes left, so a damaged length is refused before anything is allocated for it.
  std::uint64_t length(std::size_t element_bytes);
  bool at_end() const { return position_ == bytes_.size(); }
  std::size_t remaining() const { return bytes_.size() - position_; }
  // Throws CheckpointError unless every byte has been read (a state longer than its reader expects).
  void expect_end() const;
  // A value that must equal what this run has (a particle count, a realization index), named in the error.
  template <class T>
  void expect(const T& value, const char* what) {
    if (read<T>() != value) throw CheckpointError(std::string("the checkpoint's ") + what + " differs from this run's");
  }

 private:
  const char* take(std::uint64_t n);
  std::string_view bytes_;
  std::size_t position_ = 0;
};

struct CheckpointHeader {
  std::string aggkit_version;
  std::string engine;                 // the engine's name and label, "dem:collapse"
  std::uint64_t scene_fingerprint = 0;  // fnv1a64 of the scene's text
};

// 2: the ED event queue became a 4-ary heap (a checkpoint keeps the heap as it is), and the ED broad phase
//    registers passengers only up to the coarsest populated level.
constexpr std::uint32_t checkpoint_format_version = 2;

// Writes header + payload to `path` atomically (see above); throws CheckpointError if the file system fails.
void write_checkpoint(const std::filesystem::path& path, const CheckpointHeader& header, std::string_view payload);
// The payload of the checkpoint at `path`, after every check above against `expected`; CheckpointError if any
// fails (its message says which and, for a mismatch, both values).
std::string read_checkpoint(const std::filesystem::path& path, const CheckpointHeader& expected);

}  // namespace aggkit
