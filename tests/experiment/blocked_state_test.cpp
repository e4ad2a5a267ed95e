// Tests for src/cdpowder/experiment/blocked_state.cpp: the piston is blocked after a full window
// of steps at rest; each rest criterion, violated once, restarts the count (physics.md §9).
#include "cdpowder/experiment/blocked_state.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace cdpowder {
namespace {

constexpr double kDt = 0.01;     // Δt [t0]
constexpr double kWindow = 0.1;  // [t0]: 10 steps of kDt
constexpr std::int64_t kWindowSteps = 10;
constexpr double kHeight = 10.0;  // Z_P [R]
constexpr double kForce = 1.0;    // F > 0, the piston is loaded [F_coh]

// Thresholds as in scene.hpp's defaults, written out so the test does not move with them.
constexpr double kPistonSpeed = 1e-7;   // [R/t0]
constexpr double kSphereSpeed = 1e-6;   // [R/t0]
constexpr double kForceBalance = 1e-3;  // [-]
constexpr double kHeightChange = 1e-6;  // [-]

// Just below / just above a threshold. 5 % is far above the round-off of the drift
// |ΔZ_P|/Z_P (≈ 1e-16 / 1e-6 relative), so which side a value lies on is never in doubt.
constexpr double kJustBelow = 0.95;
constexpr double kJustAbove = 1.05;

// Steps at rest before the probed step, so that a reset is visible as held 5 → 0.
constexpr std::int64_t kStepsBefore = 5;

BlockedCriteria criteria() {
  BlockedCriteria c;
  c.window = kWindow;
  c.piston_speed = kPistonSpeed;
  c.sphere_speed = kSphereSpeed;
  c.force_balance = kForceBalance;
  c.height_change = kHeightChange;
  return c;
}

/// A world whose loaded piston stands still at kHeight; no spheres are needed.
World piston_world(bool enabled = true) {
  World world;
  world.walls.piston.enabled = enabled;
  world.walls.piston.force = kForce;
  world.walls.piston.height = kHeight;
  world.walls.piston.velocity = 0.0;
  return world;
}

/// Diagnostics of a step with every sphere at rest and the piston in force balance.
StepDiagnostics at_rest() {
  return StepDiagnostics{};
}

enum class Criterion { PistonSpeed, SphereSpeed, ForceBalance, HeightDrift };

/// steps_held() after kStepsBefore steps at rest and one step where `criterion` sits at
/// `factor` × its threshold; every other criterion is met throughout.
std::int64_t held_after_probe(Criterion criterion, double factor) {
  BlockedStateDetector detector(criteria(), kDt);
  World world = piston_world();
  StepDiagnostics diagnostics = at_rest();
  // The window starts at Z_P,0; the probe moves the piston down to kHeight, so that the
  // drift |Z_P − Z_P,0| / Z_P is exactly factor × height_change.
  if (criterion == Criterion::HeightDrift) {
    world.walls.piston.height = kHeight * (1.0 + factor * kHeightChange);
  }
  for (std::int64_t i = 0; i < kStepsBefore; ++i) {
    EXPECT_FALSE(detector.update(world, diagnostics));
  }
  EXPECT_EQ(detector.steps_held(), kStepsBefore);
  switch (criterion) {
    case Criterion::PistonSpeed:
      world.walls.piston.velocity = -factor * kPistonSpeed;  // moving down: |V_P| counts
      break;
    case Criterion::SphereSpeed:
      diagnostics.max_speed = factor * kSphereSpeed;
      break;
    case Criterion::ForceBalance:
      diagnostics.piston_imbalance = factor * kForceBalance;
      break;
    case Criterion::HeightDrift:
      world.walls.piston.height = kHeight;
      break;
  }
  EXPECT_FALSE(detector.update(world, diagnostics));
  return detector.steps_held();
}

TEST(BlockedStateDetector, BlocksAtTheLastStepOfTheWindowAndNotBefore) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = piston_world();
  for (std::int64_t step = 1; step < kWindowSteps; ++step) {
    EXPECT_FALSE(detector.update(world, at_rest())) << "step " << step;
    EXPECT_EQ(detector.steps_held(), step);
  }
  EXPECT_TRUE(detector.update(world, at_rest()));
  EXPECT_EQ(detector.steps_held(), kWindowSteps);
}

TEST(BlockedStateDetector, PistonSpeedJustBelowThresholdKeepsCounting) {
  EXPECT_EQ(held_after_probe(Criterion::PistonSpeed, kJustBelow), kStepsBefore + 1);
}

TEST(BlockedStateDetector, PistonSpeedJustAboveThresholdResetsCount) {
  EXPECT_EQ(held_after_probe(Criterion::PistonSpeed, kJustAbove), 0);
}

TEST(BlockedStateDetector, SphereSpeedJustBelowThresholdKeepsCounting) {
  EXPECT_EQ(held_after_probe(Criterion::SphereSpeed, kJustBelow), kStepsBefore + 1);
}

TEST(BlockedStateDetector, SphereSpeedJustAboveThresholdResetsCount) {
  EXPECT_EQ(held_after_probe(Criterion::SphereSpeed, kJustAbove), 0);
}

TEST(BlockedStateDetector, ForceImbalanceJustBelowThresholdKeepsCounting) {
  EXPECT_EQ(held_after_probe(Criterion::ForceBalance, kJustBelow), kStepsBefore + 1);
}

TEST(BlockedStateDetector, ForceImbalanceJustAboveThresholdResetsCount) {
  EXPECT_EQ(held_after_probe(Criterion::ForceBalance, kJustAbove), 0);
}

TEST(BlockedStateDetector, HeightDriftJustBelowThresholdKeepsCounting) {
  EXPECT_EQ(held_after_probe(Criterion::HeightDrift, kJustBelow), kStepsBefore + 1);
}

TEST(BlockedStateDetector, HeightDriftJustAboveThresholdResetsCount) {
  EXPECT_EQ(held_after_probe(Criterion::HeightDrift, kJustAbove), 0);
}

TEST(BlockedStateDetector, DisabledPistonNeverBlocks) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = piston_world(/*enabled=*/false);
  constexpr std::int64_t kManyWindows = 10 * kWindowSteps;
  for (std::int64_t step = 1; step <= kManyWindows; ++step) {
    EXPECT_FALSE(detector.update(world, at_rest())) << "step " << step;
    EXPECT_EQ(detector.steps_held(), 0);
  }
}

}  // namespace
}  // namespace cdpowder
