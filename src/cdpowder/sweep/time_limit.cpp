// time_limit.cpp — see time_limit.hpp.
#include "cdpowder/sweep/time_limit.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>

namespace cdpowder {

std::optional<double> parse_duration(std::string_view text) {
  if (text.empty()) return std::nullopt;
  // units in the order they must appear, with their length in seconds
  constexpr std::string_view kUnits = "hms";
  constexpr std::array<double, 3> kSeconds = {3600.0, 60.0, 1.0};
  double total = 0.0;
  std::size_t next_unit = 0;  // units before this one are used up
  std::size_t pos = 0;
  while (pos < text.size()) {
    double value = 0.0;
    const char* first = text.data() + pos;
    const auto [end, error] = std::from_chars(first, text.data() + text.size(), value);
    if (error != std::errc{} || !std::isfinite(value) || value < 0.0) return std::nullopt;
    pos += static_cast<std::size_t>(end - first);
    if (pos == text.size()) {  // a bare number: seconds, and only on its own
      if (next_unit != 0) return std::nullopt;
      return value;
    }
    const std::size_t unit = kUnits.find(text[pos], next_unit);
    if (unit == std::string_view::npos) return std::nullopt;
    total += value * kSeconds[unit];
    next_unit = unit + 1;
    ++pos;
  }
  if (!std::isfinite(total)) return std::nullopt;  // "1e308h"
  return total;
}

std::optional<double> expected_run_seconds(const SweepPlan& plan,
                                           const std::vector<std::optional<RunRecord>>& records,
                                           std::size_t run) {
  std::optional<double> same_point;
  std::optional<double> any;
  for (std::size_t i = 0; i < records.size() && i < plan.runs.size(); ++i) {
    if (!records[i]) continue;
    const double seconds = records[i]->wall_seconds;
    any = std::max(any.value_or(seconds), seconds);
    if (plan.runs[i].point == plan.runs[run].point) {
      same_point = std::max(same_point.value_or(seconds), seconds);
    }
  }
  return same_point ? same_point : any;
}

bool may_start_within(double elapsed, std::optional<double> expected, double limit) {
  if (elapsed >= limit) return false;
  return !expected || elapsed + kRunTimeMargin * *expected <= limit;
}

}  // namespace cdpowder
