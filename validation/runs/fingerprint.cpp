#include "validation/runs/fingerprint.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>

#include "analysis/input_error.hpp"
#include "particle/common/checkpoint.hpp"

namespace aggkit {

std::uint64_t text_fingerprint(std::string_view text) { return fnv1a64(text); }

std::string fingerprint_text(std::uint64_t fingerprint) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fingerprint));
  return hex;
}

std::uint64_t scene_fingerprint(const std::filesystem::path& scene, const std::string& key) {
  std::ifstream in(scene, std::ios::binary);
  if (!in) throw InputError(key, scene.string(), "a readable scene file");
  return text_fingerprint(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
}

}  // namespace aggkit
