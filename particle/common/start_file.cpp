#include "particle/common/start_file.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

std::vector<std::string> column_names(int dimension) {
  if (dimension == 2) return {"x", "y", "vx", "vy", "radius", "mass"};
  return {"x", "y", "z", "vx", "vy", "vz", "radius", "mass"};
}

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trimmed(std::string_view(line).substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const auto& w : words) {
    if (!text.empty()) text += ',';
    text += w;
  }
  return text;
}

}  // namespace

std::string start_file_header(int dimension) { return joined(column_names(dimension)); }

std::string StartFile::where(std::size_t particle) const {
  return path.string() + " line " + std::to_string(lines.at(particle));
}

StartFile read_start_file(const std::filesystem::path& path, int dimension) {
  std::string shown = "\"";
  shown += path.string() + "\"";
  const auto fail = [&](const std::string& allowed) { throw InputError("initial.file", shown, allowed); };
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) fail("a CSV start file, not a folder");
  std::ifstream in(path);
  if (!in) fail(std::string("a readable CSV start file (") + std::strerror(errno) + ")");

  const std::vector<std::string> names = column_names(dimension);
  StartFile file;
  file.path = path;
  std::string line;
  std::size_t number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trimmed(line).empty()) continue;
    const std::string at = "line " + std::to_string(number) + ": ";
    const std::vector<std::string> cells = cells_of(line);
    if (!header) {
      if (cells != names)
        fail(at + "the header line must be " + joined(names) + " (" + std::to_string(dimension) + "-D), not " + trimmed(line));
      header = true;
      continue;
    }
    if (cells.size() != names.size())
      fail(at + std::to_string(cells.size()) + " columns, expected " + std::to_string(names.size()) + " (" + joined(names) + ")");
    std::vector<double> row(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      std::string_view text = cells[c];
      if (!text.empty() && text.front() == '+') text.remove_prefix(1);
      const auto [end, status] = std::from_chars(text.data(), text.data() + text.size(), row[c]);
      if (cells[c].empty() || status != std::errc() || end != text.data() + text.size())
        fail(at + names[c] + " = \"" + cells[c] + "\" is not a number");
      if (!std::isfinite(row[c])) fail(at + names[c] + " = " + format_value(row[c]) + " is not finite");
    }
    const double radius = row[names.size() - 2], mass = row[names.size() - 1];
    if (!(radius > 0)) fail(at + "radius = " + format_value(radius) + ": a radius must be > 0");
    if (!(mass > 0)) fail(at + "mass = " + format_value(mass) + ": a mass must be > 0");
    Vector3 x{0, 0, 0}, v{0, 0, 0};
    for (int a = 0; a < dimension; ++a) {
      x[a] = row[std::size_t(a)];
      v[a] = row[std::size_t(dimension + a)];
    }
    file.particles.positions.push_back(x);
    file.particles.velocities.push_back(v);
    file.particles.radii.push_back(radius);
    file.particles.masses.push_back(mass);
    file.lines.push_back(number);
  }
  if (in.bad()) fail(std::string("a readable CSV start file (") + std::strerror(errno) + ")");
  if (!header) fail("a CSV start file with the header line " + joined(names) + ", then one particle per line (it is empty)");
  if (file.particles.size() == 0) fail("at least one particle line after the header");
  return file;
}

void write_start_file(const std::filesystem::path& path, int dimension, const ParticleStart& start) {
  std::ofstream out(path);
  out << start_file_header(dimension) << '\n';
  for (std::size_t i = 0; i < start.size(); ++i) {
    std::string line;
    const auto add = [&](double value) {
      if (!line.empty()) line += ',';
      line += format_value(value);
    };
    for (int a = 0; a < dimension; ++a) add(start.positions[i][a]);
    for (int a = 0; a < dimension; ++a) add(start.velocities[i][a]);
    add(start.radii[i]);
    add(start.masses[i]);
    out << line << '\n';
  }
  out.flush();
  if (!out) throw std::runtime_error("cannot write the start file " + path.string());
}

}  // namespace aggkit
