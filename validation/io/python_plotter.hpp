#pragma once
// What the matplotlib plotters (report.png, final.png, phase_diagram.png) share: the Python interpreter
// they run under — $AGGKIT_PYTHON, else /usr/bin/python3 (Debian's, with python3-matplotlib), else python3
// on PATH —, where its script is found, and the last non-blank line of a plotter's output (its exception
// message).
#include <filesystem>
#include <string>

namespace aggkit {

std::string plot_interpreter();
std::string last_output_line(const std::string& text);
// A plotter script: $<environment> if set, else `build` (the source tree's copy) if it exists, else
// `install` (the copy `cmake --install` puts under share/aggkit).
std::filesystem::path plot_script(const char* environment, const char* build, const char* install);

}  // namespace aggkit
