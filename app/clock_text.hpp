// clock_text.hpp — wall-clock durations as people read them on a progress line.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace cdpowder::app {

/// "MM:SS" below an hour, "H:MM:SS" from an hour on (seconds rounded to the nearest).
inline std::string clock_text(double seconds) {
  const long s = std::lround(seconds);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{:02}:{:02}", s / 60, s % 60);
}

}  // namespace cdpowder::app
