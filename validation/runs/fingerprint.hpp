#pragma once
// Fingerprints of what a result depends on (a scene's text and how it is run): FNV-1a, 64 bits — stable
// across builds and machines, unlike std::hash; not a cryptographic hash. A resumed run reuses an earlier
// result only while its fingerprint is unchanged: the checkpoints of `aggkit run` (run.json and each state
// file's header), the finished scenes of `aggkit validate` (finished/<scene>.json) and Python's aggkit.run.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace aggkit {

std::uint64_t text_fingerprint(std::string_view text);
// As written in the run folders' records: 16 lower-case hexadecimal digits.
std::string fingerprint_text(std::uint64_t fingerprint);
// The fingerprint of a scene file's text; InputError naming `key` if it cannot be read.
std::uint64_t scene_fingerprint(const std::filesystem::path& scene, const std::string& key);

}  // namespace aggkit
