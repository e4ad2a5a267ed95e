// Tests for src/cdpowder/solver/time_step_control.cpp: each bound of the adaptive Δt alone.
#include "cdpowder/solver/time_step_control.hpp"

#include <gtest/gtest.h>

namespace cdpowder {
namespace {

constexpr double kSkin = 0.05;

/// One unit sphere at rest, cohesion range 0.01 for spheres and walls.
struct OneSphere {
  OneSphere() {
    world.bodies.add_sphere(Vec3(0.0, 0.0, 1.0), 1.0, 1.0);
    laws.spheres.cohesion_range = laws.walls.cohesion_range = 0.01;
    control.adaptive = true;
    control.dt_max = 0.05;  // the tests below are written for these bounds
    control.dt_min = 1e-4;
  }

  World world;
  ContactLaws laws;
  TimeStepControl control;

  [[nodiscard]] double next(double dt, double opening_speed) const {
    return next_time_step(control, dt, surface_motion(world), opening_speed, laws, kSkin);
  }
};

TEST(TimeStepControl, AtRestItGrowsByTheGrowthFactorUpToDtMax) {
  const OneSphere s;
  EXPECT_DOUBLE_EQ(s.next(0.01, 0.0), 0.012);
  EXPECT_DOUBLE_EQ(s.next(0.045, 0.0), 0.05);
}

TEST(TimeStepControl, TheOpeningSpeedBoundsIt) {
  const OneSphere s;
  // V_n = 0.1 R/t0: opening_per_step 0.05 of d_coh 0.01 R allows Δt = 0.005
  EXPECT_DOUBLE_EQ(s.next(0.01, 0.1), 0.05 * 0.01 / 0.1);
}

TEST(TimeStepControl, TheSmallerCohesionRangeOfTheTwoLawsCounts) {
  OneSphere s;
  s.laws.walls.cohesion_range = 0.002;
  EXPECT_DOUBLE_EQ(s.next(0.01, 0.1), 0.05 * 0.002 / 0.1);
  s.laws.walls.cohesion_force = 0.0;  // a wall without cohesion does not bound it
  EXPECT_DOUBLE_EQ(s.next(0.01, 0.1), 0.05 * 0.01 / 0.1);
}

TEST(TimeStepControl, TheFastestSurfaceBoundsIt) {
  OneSphere s;
  // |v| + R|ω| = 0.3 + 1·0.2 = 0.5 R/t0: 0.2 × min(R, skin) = 0.01 R per step, Δt = 0.02
  s.world.bodies.velocity[0] = Vec3(0.0, 0.3, 0.0);
  s.world.bodies.angular_velocity[0] = Vec3(0.2, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(s.next(0.05, 0.0), 0.2 * kSkin / 0.5);
  // the piston too
  s.world.bodies.velocity[0].setZero();
  s.world.bodies.angular_velocity[0].setZero();
  s.world.walls.piston.enabled = true;
  s.world.walls.piston.velocity = -1.0;
  EXPECT_DOUBLE_EQ(s.next(0.05, 0.0), 0.2 * kSkin / 1.0);
}

TEST(TimeStepControl, ItNeverLeavesItsBounds) {
  const OneSphere s;
  EXPECT_DOUBLE_EQ(s.next(0.01, 1e9), s.control.dt_min);
}

TEST(TimeStepControl, ARepeatedStepIsScaledToTheTargetAndAtLeastHalved) {
  TimeStepControl control;
  // opened 0.2 d_coh at Δt = 0.04: the target 0.05 needs Δt = 0.01
  EXPECT_DOUBLE_EQ(retry_time_step(control, 0.04, 0.2), 0.01);
  EXPECT_DOUBLE_EQ(retry_time_step(control, 2e-4, 100.0), control.dt_min);
  // a target close to the bound would shorten a step just above it by little: halved
  control.opening_per_step = 0.09;
  EXPECT_DOUBLE_EQ(retry_time_step(control, 0.04, 0.11), 0.02);
}

}  // namespace
}  // namespace cdpowder
