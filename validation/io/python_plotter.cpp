#include "validation/io/python_plotter.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace aggkit {

std::string plot_interpreter() {
  if (const char* python = std::getenv("AGGKIT_PYTHON"); python && *python) return python;
  std::error_code error;
  if (std::filesystem::exists("/usr/bin/python3", error)) return "/usr/bin/python3";
  return "python3";
}

std::string last_output_line(const std::string& text) {
  std::size_t end = text.find_last_not_of(" \n\r\t");
  if (end == std::string::npos) return "";
  const std::size_t begin = text.rfind('\n', end);
  const std::size_t first = begin == std::string::npos ? 0 : begin + 1;
  return text.substr(first, end - first + 1);
}

std::filesystem::path plot_script(const char* environment, const char* build, const char* install) {
  if (const char* script = std::getenv(environment); script && *script) return script;
  std::error_code error;
  if (std::filesystem::exists(build, error)) return build;
  return install;
}

}  // namespace aggkit
