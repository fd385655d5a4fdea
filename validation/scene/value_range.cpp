#include "validation/scene/value_range.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace aggkit {

std::vector<double> read_value_range(const SceneTable& range, std::size_t max_count, bool& log_spacing) {
  range.allow_only({"from", "to", "count", "spacing"});
  const double from = range.number("from", Bound::finite);
  const double to = range.number("to", Bound::finite);
  const std::size_t count = range.count("count", 0);
  if (count == 0) range.fail("count", "at least 1 (an empty range scans nothing)");
  if (count > max_count) range.fail("count", "at most " + std::to_string(max_count));
  const std::string spacing = range.optional_string("spacing").value_or("linear");
  if (spacing != "linear" && spacing != "log") range.fail("spacing", "\"linear\" or \"log\"");
  log_spacing = spacing == "log";
  if (count == 1 && to != from) range.fail("count", "at least 2 for a range with from != to");
  if (count > 1 && !(to > from))
    range.fail("to", "greater than from = " + shortest_text(from) + " (the range would be empty)");
  if (log_spacing && !(from > 0)) range.fail("from", "> 0 for spacing = \"log\"");
  std::vector<double> values;
  for (std::size_t i = 0; i < count; ++i) {
    const double s = count == 1 ? 0.0 : double(i) / double(count - 1);
    const double value = log_spacing ? from * std::pow(to / from, s) : from + (to - from) * s;
    char text[32];
    std::snprintf(text, sizeof text, "%.12g", value);
    values.push_back(std::strtod(text, nullptr));
  }
  values.back() = to;  // exactly the end of the range, free of round-off
  return values;
}

}  // namespace aggkit
