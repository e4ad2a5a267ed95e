// duration.cpp — parse_duration (duration.hpp).
#include "duration.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <system_error>

namespace cdpowder::app {

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

}  // namespace cdpowder::app
