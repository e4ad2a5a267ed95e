// duration_test.cpp — `--time-limit` durations as written on the command line (app/).
#include "duration.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <utility>
#include <vector>

namespace cdpowder::app {
namespace {

TEST(ParseDuration, ReadsSecondsAndUnitsLargestFirst) {
  const std::vector<std::pair<const char*, double>> cases = {
      {"5400", 5400.0},
      {"0.5", 0.5},
      {"45s", 45.0},
      {"90m", 5400.0},
      {"2.5h", 9000.0},
      {"2h40m", 9600.0},
      {"1h5m30s", 3930.0},
      {"1h30s", 3630.0},
      {"0", 0.0},
      // what std::from_chars reads as a number
      {".5", 0.5},
      {"5.", 5.0},
      {"1e3", 1000.0},
      {"1.5m", 90.0}};
  for (const auto& [text, seconds] : cases) EXPECT_EQ(parse_duration(text), seconds) << text;
}

TEST(ParseDuration, RefusesWhatIsNotADuration) {
  for (const char* text : {"", "h", "2x", "2 h", "-5", "-1m", "2h30", "30m2h", "1h1h", "inf", "nan",
                           "1e400", "5m ", "m5", "+5", "1h-5m", "1e308h", "5mm"}) {
    EXPECT_EQ(parse_duration(text), std::nullopt) << text;
  }
}

}  // namespace
}  // namespace cdpowder::app
