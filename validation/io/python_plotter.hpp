#pragma once
// What the matplotlib plotters (report.png, final.png, phase_diagram.png) share: the Python interpreter
// they run under — $AGGKIT_PYTHON, else /usr/bin/python3 (Debian's, with python3-matplotlib), else python3
// on PATH —, where its script is found, and the last non-blank line of a plotter's output (its exception
// message).
#include <filesystem>
#include <string>
#include <vector>

namespace aggkit {

std::string plot_interpreter();
std::string last_output_line(const std::string& text);
// A plotter script: $<environment> if set, else `build` (the source tree's copy) if it exists, else
// `install` (the copy `cmake --install` puts under share/aggkit).
std::filesystem::path plot_script(const char* environment, const char* build, const char* install);

// A plotter started before its data exists (validation/io/child_process.hpp's StartedProcess), so that the
// interpreter's matplotlib import overlaps the run: the command imports matplotlib (Agg; a failed import is
// left for the script to meet and report as it would alone), then reads the script's arguments from stdin,
// each ending in '\0', and runs `script` as __main__ with them as sys.argv. Stdin closed without arguments
// (the run ended otherwise): it exits silently.
std::vector<std::string> started_plot_command(const std::filesystem::path& script);
std::string started_plot_input(const std::vector<std::string>& arguments);

}  // namespace aggkit
