#pragma once
// The files a cycle column's step is cached in (DIR/points/cycle_column_a*_lambda*_N*): its record (.csv, one
// row under a versioned header: records of earlier versions are read back with what they lack as unknown), the
// state it ended in (_state.txt) and its largest Floquet multiplier (_floquet.csv). The walk itself is
// validation/scan/scan_cycle_column.cpp.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "validation/scan/scan_cycle_column.hpp"

namespace aggkit {

std::string file_text(const ColumnCycle& c, std::size_t periods, const std::string& grid);
// The record of (a, λ) walked with `periods` periods on `grid`; nullopt where the text is not such a record, or
// is a stop under a step budget other than `step_budget` (it is run again).
std::optional<ColumnCycle> parse_file(const std::string& text, double a, double lambda, std::size_t periods,
                                      const std::string& grid, std::size_t step_budget);
std::string state_text(const std::vector<double>& state);
std::optional<std::vector<double>> parse_state(const std::string& text, std::size_t unknowns);
std::string floquet_text(const ColumnCycle& c);
void parse_floquet(const std::string& text, ColumnCycle& c);

}  // namespace aggkit
