#pragma once
// The command-line tests build shell commands for std::system: one word in single quotes, with embedded
// single quotes closed, escaped and reopened ('\''), so paths and scene text pass through unchanged.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "tests/validation/scene_fixture.hpp"

namespace aggkit::testing {

inline std::string quoted(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A command's exit status and its standard error (stdout discarded), the latter kept in FOLDER/stderr.txt.
struct CommandOutcome {
  int exit_code;
  std::string err;
};

inline CommandOutcome run_command(const std::string& command, const std::filesystem::path& folder) {
  const auto err = folder / "stderr.txt";
  const int status = std::system((command + " >/dev/null 2>" + quoted(err.string())).c_str());
  REQUIRE(WIFEXITED(status));
  return {WEXITSTATUS(status), read_text(err)};
}

// A CSV file as rows of (column name -> text); a row ending in ',' has an empty last field. Every row must
// have the header's number of fields.
using CsvTable = std::vector<std::map<std::string, std::string>>;
inline CsvTable read_csv(const std::filesystem::path& file) {
  std::istringstream in(read_text(file));
  const auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream fields(text);
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (!text.empty() && text.back() == ',') cells.emplace_back();
    return cells;
  };
  std::string line;
  std::vector<std::string> header;
  CsvTable rows;
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    REQUIRE(cells.size() == header.size());
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

// The prefix that starts a command on RANKS MPI ranks (as root, more ranks than cores allowed).
inline std::string mpirun(int ranks) {
  return quoted(AGGKIT_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
}

}  // namespace aggkit::testing
