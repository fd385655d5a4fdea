// bench/figures.hpp: the rows a bench program appends are the CSV bench/check reads (RFC 4180 quoting, one
// header, rows accumulating across runs).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/figures.hpp"

namespace {

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

TEST_CASE("bench figures: rows accumulate under one header, quoted where needed") {
  const auto folder = std::filesystem::path(AGGKIT_TEST_TMP) / "bench-figures";
  std::filesystem::remove_all(folder);
  ::setenv("AGGKIT_BENCH_FIGURES", folder.c_str(), 1);
  char name[] = "/some/where/bench_demo", arg[] = "1e6";
  char* argv[] = {name, arg};
  {
    const aggkit::bench::Figures figures("demo", 2, argv);
    CHECK(figures.folder() == folder);
    figures.add("n=1e6, method=\"ar\"", "wall_seconds", 7.25, "s");
    figures.add("", "error", std::nan(""), "1");
  }
  const aggkit::bench::Figures again("demo", 2, argv);
  again.add("n=10", "wall_seconds", 0.5, "s");
  ::unsetenv("AGGKIT_BENCH_FIGURES");
  const auto lines = lines_of(folder / "demo.csv");
  REQUIRE(lines.size() == 4);
  CHECK(lines[0] == "date,bench,case,figure,value,unit,command");
  // date: 2026-12-01T19:00:00Z form, then the quoted case with its comma and doubled quotes
  CHECK(lines[1].size() > 21);
  CHECK(lines[1][10] == 'T');
  CHECK(lines[1][19] == 'Z');
  CHECK(lines[1].substr(21) == "demo,\"n=1e6, method=\"\"ar\"\"\",wall_seconds,7.25,s,build/bench/bench_demo 1e6");
  CHECK(lines[2].substr(21) == "demo,,error,nan,1,build/bench/bench_demo 1e6");
  CHECK(lines[3].substr(21) == "demo,n=10,wall_seconds,0.5,s,build/bench/bench_demo 1e6");
}
