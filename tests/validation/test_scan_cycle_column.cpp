// How the points take what their column found (validation/scan/scan_cycle_column.hpp): the sustained run where the
// steady state is unstable, the multiplier where the point's own run confirmed the cycle, and bistability where
// the steady state is stable and the column's cycle settled at the same λ.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "validation/scan/scan_cycle_column.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

// A settled column step at (a, λ) with a measured multiplier: brownian a = 0.6, λ = 3.16e-9 as walked on the
// shipped scan's grid (period 8.17e7, M0 4.7e-5 .. 8.9e-5).
ColumnCycle settled_step(double a, double lambda) {
  ColumnCycle c;
  c.a = a;
  c.lambda = lambda;
  c.from_lambda = 1e-8;
  c.classified = true;
  c.run.regime = Regime::sustained;
  c.run.converged = true;
  c.run.period = 8.16855e7;
  c.settling = CycleSettling::settled;
  c.m0_min = 4.69977e-5;
  c.m0_max = 8.87076e-5;
  c.floquet.multiplier = 0.12;
  c.floquet.note = "from the decay over returns 1 to 3";
  c.floquet_done = true;
  return c;
}

ScanRecord point(double a, double lambda, const std::string& verdict, double re) {
  ScanRecord r;
  r.a = a;
  r.lambda = lambda;
  r.verdict = verdict;
  r.rightmost_real = re;
  r.rightmost_imag = 1.17e-7;
  return r;
}

}  // namespace

TEST_CASE("scan columns: a stable focus beside the column's settled cycle is bistable, with the cycle's figures") {
  const double a = 0.6, lambda = 3.16227766017e-9;
  CycleColumns columns;
  columns[{a, lambda}] = settled_step(a, lambda);
  std::vector<ScanRecord> records{point(a, lambda, "damped", -1.378e-9), point(a, 1e-7, "damped", -1.5e-8)};
  adopt_column_cycles(columns, 12, records);
  const ScanRecord& r = records.front();
  INFO(r.note);
  CHECK(r.verdict == "bistable");
  CHECK(r.cycle_period == 8.16855e7);
  CHECK(r.cycle_m0_min == 4.69977e-5);
  CHECK(r.cycle_m0_max == 8.87076e-5);
  CHECK(r.floquet_max == 0.12);
  CHECK(r.cycle_stable == "yes");
  CHECK_THAT(r.note, Contains("bistable: the steady state is a stable focus") && Contains("attracts here too"));
  // Where the column has no step, the stable focus stays damped.
  CHECK(records.back().verdict == "damped");
  CHECK(std::isnan(records.back().cycle_period));
}

TEST_CASE("scan columns: an unsettled column step makes no point bistable, and a sustained point takes the multiplier") {
  const double a = 0.6, lambda = 3.16227766017e-9;
  CycleColumns columns;
  ColumnCycle unsettled = settled_step(a, lambda);
  unsettled.run.converged = false;
  unsettled.settling = CycleSettling::unsettled;
  columns[{a, lambda}] = unsettled;
  columns[{a, 1e-8}] = settled_step(a, 1e-8);
  ScanRecord confirmed = point(a, 1e-8, "sustained", 2.4e-9);
  confirmed.regime = "sustained";
  std::vector<ScanRecord> records{point(a, lambda, "damped", -1.378e-9), confirmed};
  adopt_column_cycles(columns, 12, records);
  CHECK(records.front().verdict == "damped");
  CHECK(std::isnan(records.front().floquet_max));
  CHECK(records.back().verdict == "sustained");
  CHECK(records.back().floquet_max == 0.12);
  CHECK_THAT(records.back().note, Contains("the column's cycle: largest nontrivial Floquet multiplier from the return map 0.12"));
}

TEST_CASE("scan columns: a sustained point says where its column's cycle reaches the grid's end") {
  // The same settled step twice: its run's top octave held 2e-4 of the mass (as a = 0.7, λ = 3.16e-11 at a crossing
  // on N = 2^40) and 1e-9 (the integrator's level, below the 1e-6 mark): only the first says so.
  const double a = 0.7;
  CycleColumns columns;
  for (const auto& [lambda, top] : {std::pair{1e-10, 2e-4}, std::pair{1e-9, 1e-9}}) {
    ColumnCycle c = settled_step(a, lambda);
    c.top_octave_mass = top;
    c.leaked_mass = 3e-8;
    columns[{a, lambda}] = c;
  }
  std::vector<ScanRecord> records{point(a, 1e-10, "unstable", 2e-11), point(a, 1e-9, "unstable", 2e-10)};
  adopt_column_cycles(columns, 12, records);
  CHECK(records.front().verdict == "sustained");
  CHECK_THAT(records.front().note, Contains("the cycle reaches the grid's end (its top octave held up to 0.0002 of the mass"));
  CHECK(records.back().verdict == "sustained");
  CHECK(records.back().note.find("grid's end") == std::string::npos);
}
