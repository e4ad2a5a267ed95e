// Tests for src/cdpowder/io/cadence.hpp: step and time cadences of the periodic outputs.
#include "cdpowder/io/cadence.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace cdpowder {
namespace {

TEST(Cadence, EveryKStepsIsDueAtTheMultiplesOfK) {
  Cadence cadence(3, 0.0);
  World world;
  std::vector<std::int64_t> due;
  for (world.step = 1; world.step <= 10; ++world.step) {
    if (cadence.due(world)) due.push_back(world.step);
  }
  EXPECT_EQ(due, (std::vector<std::int64_t>{3, 6, 9}));
}

// Steps of uneven length: due at the first step that reaches each multiple of the interval,
// once, also when one step jumps over a multiple.
TEST(Cadence, AnIntervalIsDueOncePerMultipleOfTime) {
  Cadence cadence(1, 0.5);  // the interval wins over the step count
  World world;
  std::vector<double> due;
  for (const double dt : {0.2, 0.2, 0.2, 0.3, 0.7, 0.05, 0.05, 0.1}) {
    world.time += dt;
    ++world.step;
    if (cadence.due(world)) due.push_back(world.time);
  }
  // times 0.2 0.4 0.6 0.9 1.6 1.65 1.7 1.8: the first step, then the first past 0.5, 1.0 (1.6
  // passes 1.0 and 1.5 at once: one row)
  ASSERT_EQ(due.size(), 3U);
  EXPECT_DOUBLE_EQ(due[0], 0.2);
  EXPECT_DOUBLE_EQ(due[1], 0.6);
  EXPECT_DOUBLE_EQ(due[2], 1.6);
}

// Summed steps carry round-off (ten steps of 0.1 are 0.9999999999999999): the multiple is
// still reached at the tenth step, not the eleventh.
TEST(Cadence, RoundOffOfSummedStepsDoesNotDelayARecord) {
  Cadence cadence(0, 1.0);
  World world;
  EXPECT_TRUE(cadence.due(world));  // t = 0
  int due_at = 0;
  for (int k = 1; k <= 12 && due_at == 0; ++k) {
    world.time += 0.1;
    if (cadence.due(world)) due_at = k;
  }
  EXPECT_EQ(due_at, 10);
}

TEST(Cadence, NeitherStepsNorIntervalIsNeverDue) {
  Cadence cadence(0, 0.0);
  EXPECT_FALSE(cadence.enabled());
  World world;
  world.step = 5;
  EXPECT_FALSE(cadence.due(world));
}

}  // namespace
}  // namespace cdpowder
