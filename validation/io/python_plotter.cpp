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

namespace {

// sys.path[0] is the script's folder, as when the interpreter runs the script itself.
constexpr const char* started_plot_bootstrap = R"(import os, sys
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot
except Exception:
    pass
data = sys.stdin.buffer.read()
if not data:
    sys.exit(0)
script = sys.argv[1]
sys.argv = [script] + [os.fsdecode(a) for a in data.split(b"\0")[:-1]]
sys.path[0] = os.path.dirname(os.path.abspath(script))
import runpy
runpy.run_path(script, run_name="__main__")
)";

}  // namespace

std::vector<std::string> started_plot_command(const std::filesystem::path& script) {
  return {plot_interpreter(), "-c", started_plot_bootstrap, script.string()};
}

std::string started_plot_input(const std::vector<std::string>& arguments) {
  std::string input;
  for (const auto& a : arguments) {
    input += a;
    input += '\0';
  }
  return input;
}

}  // namespace aggkit
