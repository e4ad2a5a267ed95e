// Tests for src/cdpowder/run/blocked_state.cpp: the piston is blocked after a full window
// of steps at rest (physics.md §9). Each per-step criterion (speeds, height drift), violated
// once, restarts the count; the force balance is judged on its window mean. Without a piston
// the spheres alone are watched.
#include "cdpowder/run/blocked_state.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

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

enum class Criterion { PistonSpeed, SphereSpeed, HeightDrift };

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
      diagnostics.rms_speed = factor * kSphereSpeed;
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

/// Feeds one window of steps at rest whose force imbalances repeat `pattern`; returns
/// whether the last step reported the blocked state.
bool window_with_imbalances(BlockedStateDetector& detector, const std::vector<double>& pattern) {
  const World world = piston_world();
  StepDiagnostics diagnostics = at_rest();
  bool blocked = false;
  for (std::int64_t step = 0; step < kWindowSteps; ++step) {
    diagnostics.piston_imbalance = pattern[static_cast<std::size_t>(step) % pattern.size()];
    blocked = detector.update(world, diagnostics);
    if (step + 1 < kWindowSteps) {
      EXPECT_FALSE(blocked) << "step " << step;
    }
  }
  return blocked;
}

TEST(BlockedStateDetector, ForceImbalanceMeanJustBelowThresholdBlocks) {
  BlockedStateDetector detector(criteria(), kDt);
  // alternating 0 and 1.9 × threshold: every other step is far out, the mean is 0.95 ×
  EXPECT_TRUE(window_with_imbalances(detector, {0.0, 2.0 * kJustBelow * kForceBalance}));
  EXPECT_NEAR(detector.mean_force_imbalance(), kJustBelow * kForceBalance, 1e-15);
}

TEST(BlockedStateDetector, ForceImbalanceMeanJustAboveThresholdDoesNotBlock) {
  BlockedStateDetector detector(criteria(), kDt);
  EXPECT_FALSE(window_with_imbalances(detector, {0.0, 2.0 * kJustAbove * kForceBalance}));
  // the speeds held, so the count goes on and the window slides
  EXPECT_EQ(detector.steps_held(), kWindowSteps);
}

TEST(BlockedStateDetector, OneNoisyStepInABalancedWindowStillBlocks) {
  BlockedStateDetector detector(criteria(), kDt);
  std::vector<double> pattern(kWindowSteps, 0.0);
  pattern[3] = 5.0 * kForceBalance;  // mean 0.5 × threshold
  EXPECT_TRUE(window_with_imbalances(detector, pattern));
}

TEST(BlockedStateDetector, TheWindowSlidesPastAnImbalancedStretch) {
  BlockedStateDetector detector(criteria(), kDt);
  // three windows at twice the threshold, then balanced steps
  for (int w = 0; w < 3; ++w) {
    EXPECT_FALSE(window_with_imbalances(detector, {2.0 * kForceBalance}));
  }
  const World world = piston_world();
  std::int64_t balanced = 0;
  while (!detector.update(world, at_rest())) {
    ++balanced;
    ASSERT_LT(balanced, 4 * kWindowSteps);
  }
  ++balanced;
  // a sliding mean over the last W = 10 steps, (10 − k) × 2 / 10 × threshold, falls below
  // the threshold at k = 6 balanced steps; a mean over all 30 + k steps held would need 31
  EXPECT_EQ(balanced, 6);
}

TEST(BlockedStateDetector, MeanImbalanceIsOverTheStepsHeldWhileFewerThanAWindow) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = piston_world();
  StepDiagnostics d = at_rest();
  d.piston_imbalance = 4.0;
  detector.update(world, d);
  d.piston_imbalance = 2.0;
  detector.update(world, d);
  EXPECT_DOUBLE_EQ(detector.mean_force_imbalance(), 3.0);
  // a reset (the piston moved) starts the mean afresh
  World moving = piston_world();
  moving.walls.piston.velocity = -1.0;
  detector.update(moving, d);
  EXPECT_EQ(detector.steps_held(), 0);
  EXPECT_DOUBLE_EQ(detector.mean_force_imbalance(), 0.0);
  d.piston_imbalance = 1.0;
  detector.update(world, d);
  EXPECT_DOUBLE_EQ(detector.mean_force_imbalance(), 1.0);
}

TEST(BlockedStateDetector, AOneStepWindowJudgesEachStepAlone) {
  BlockedCriteria c = criteria();
  c.window = kDt;  // one step
  BlockedStateDetector detector(c, kDt);
  World world = piston_world();
  StepDiagnostics d = at_rest();
  d.piston_imbalance = 2.0 * kForceBalance;
  EXPECT_FALSE(detector.update(world, d));
  world.walls.piston.height = kHeight * (1.0 + 0.5);  // a jump is not a drift within one step
  d.piston_imbalance = 0.5 * kForceBalance;
  EXPECT_TRUE(detector.update(world, d));
}

TEST(BlockedStateDetector, HeightDriftJustBelowThresholdKeepsCounting) {
  EXPECT_EQ(held_after_probe(Criterion::HeightDrift, kJustBelow), kStepsBefore + 1);
}

TEST(BlockedStateDetector, HeightDriftJustAboveThresholdResetsCount) {
  EXPECT_EQ(held_after_probe(Criterion::HeightDrift, kJustAbove), 0);
}

/// Whether a piston creeping down at a constant rate, such that it moves `factor` ×
/// height_change × Z_P in the W − 1 steps between a window's first and last step, is ever
/// reported blocked within `windows` windows.
bool creeping_piston_blocks(double factor, int windows) {
  BlockedStateDetector detector(criteria(), kDt);
  World world = piston_world();
  const double per_step = factor * kHeightChange * kHeight / static_cast<double>(kWindowSteps - 1);
  for (std::int64_t step = 0; step < windows * kWindowSteps; ++step) {
    if (detector.update(world, at_rest())) return true;
    world.walls.piston.height -= per_step;
  }
  return false;
}

TEST(BlockedStateDetector, PistonCreepingJustBelowTheDriftBoundBlocks) {
  EXPECT_TRUE(creeping_piston_blocks(kJustBelow, 1));
}

TEST(BlockedStateDetector, PistonCreepingJustAboveTheDriftBoundNeverBlocks) {
  EXPECT_FALSE(creeping_piston_blocks(kJustAbove, 20));
}

TEST(BlockedStateDetector, OneFastSphereInAPackingAtRestDoesNotPreventBlocking) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = piston_world();
  StepDiagnostics d = at_rest();
  d.max_speed = 0.1;                 // a rattler [R/t0]
  d.rms_speed = 0.5 * kSphereSpeed;  // the packing as a whole at rest
  bool blocked = false;
  for (std::int64_t step = 0; step < kWindowSteps; ++step) blocked = detector.update(world, d);
  EXPECT_TRUE(blocked);
}

/// Without a piston: two spheres of unit radius and density resting at heights 1 and 3.
World spheres_alone() {
  World world = piston_world(/*enabled=*/false);
  world.bodies.add_sphere(Vec3(0.0, 0.0, 1.0), 1.0, 1.0);
  world.bodies.add_sphere(Vec3(0.0, 0.0, 3.0), 1.0, 1.0);
  return world;
}

// Without a piston the spheres alone decide (a gravity settling run until_blocked): their
// speeds over a whole window, and their mean height's drift, stand in for the piston's
TEST(BlockedStateDetector, WithoutAPistonSpheresAtRestBlockAfterAWindow) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = spheres_alone();
  for (std::int64_t step = 1; step < kWindowSteps; ++step) {
    EXPECT_FALSE(detector.update(world, at_rest())) << "step " << step;
  }
  EXPECT_TRUE(detector.update(world, at_rest()));
  EXPECT_DOUBLE_EQ(detector.mean_force_imbalance(), 0.0);
  EXPECT_DOUBLE_EQ(BlockedStateDetector::watched_height(world), 2.0);
}

TEST(BlockedStateDetector, WithoutAPistonMovingSpheresNeverBlock) {
  BlockedStateDetector detector(criteria(), kDt);
  const World world = spheres_alone();
  StepDiagnostics moving = at_rest();
  moving.rms_speed = kJustAbove * kSphereSpeed;
  for (std::int64_t step = 1; step <= 3 * kWindowSteps; ++step) {
    EXPECT_FALSE(detector.update(world, moving)) << "step " << step;
    EXPECT_EQ(detector.steps_held(), 0);
  }
}

TEST(BlockedStateDetector, WithoutAPistonASinkingPackingRestartsTheWindow) {
  BlockedStateDetector detector(criteria(), kDt);
  World world = spheres_alone();
  for (std::int64_t i = 0; i < kStepsBefore; ++i) EXPECT_FALSE(detector.update(world, at_rest()));
  // the mean height 2 R sinks by more than height_change × 2 R since the window began
  for (Vec3& x : world.bodies.position) x.z() -= kJustAbove * kHeightChange * 2.0;
  EXPECT_FALSE(detector.update(world, at_rest()));
  EXPECT_EQ(detector.steps_held(), 0);
}

// The load a packing at rest is balanced against: the piston's, or the spheres' weight, and
// at least one bond's F_coh
TEST(RestingLoad, IsThePistonsLoadOrTheSpheresWeightAndAtLeastABond) {
  World world = spheres_alone();
  const double sphere_mass = world.bodies.mass(0);
  EXPECT_DOUBLE_EQ(resting_load(world, 1.0), 1.0);  // no gravity, no piston: F_coh
  world.gravity = Vec3(0.0, 0.0, -2.0);
  EXPECT_NEAR(sphere_weight(world), 4.0 * sphere_mass, 1e-12 * sphere_mass);
  EXPECT_NEAR(resting_load(world, 1e-3), 4.0 * sphere_mass, 1e-12 * sphere_mass);
  world.walls.piston.enabled = true;
  world.walls.piston.mass = 5.0;
  EXPECT_DOUBLE_EQ(resting_load(world, 1.0), kForce + 10.0);  // F + M_P |g|
}

}  // namespace
}  // namespace cdpowder
