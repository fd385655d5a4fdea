#pragma once
// What the matplotlib plotters (report.png, final.png, phase_diagram.png) share: the Python interpreter
// they run under — $AGGKIT_PYTHON, else /usr/bin/python3 (Debian's, with python3-matplotlib), else python3
// on PATH — and the last non-blank line of a plotter's output (its exception message).
#include <string>

namespace aggkit {

std::string plot_interpreter();
std::string last_output_line(const std::string& text);

}  // namespace aggkit
