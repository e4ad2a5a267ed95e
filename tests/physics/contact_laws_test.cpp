// Analytic threshold tests of the friction laws through whole time steps (physics.md
// §5.4, §15 items 3–5): just below a threshold the contact holds, just above it gives way
// and transmits exactly the threshold. Below/above are 0.95× and 1.05×.
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

namespace cdpowder::testing {
namespace {

constexpr double kBelow = 0.95;
constexpr double kAbove = 1.05;
constexpr int kSteps = 50;
// A held contact ends with velocities of round-off size; one that gives way accelerates
// at ≥ 0.05 × threshold / m for 50 steps, i.e. ≥ 1e-3 R/t0 here.
constexpr double kAtRest = 1e-9;
constexpr double kMoving = 1e-5;
// Forces at the end of a converged solve (tolerance 1e-10) [F_coh].
constexpr double kForceTol = 1e-6;

// A sphere resting on the bottom wall, loaded by F_N towards the wall at its centre and
// pushed sideways by P at its centre. Rolling blocked (μ_t large): friction carries P.
TinyScene sphere_on_wall(double load, double push, double mu_roll) {
  TinyScene s(10.0, 10.0);
  s.world.walls.bottom.enabled = true;
  s.settings.laws.walls.mu_roll = mu_roll;
  const BodyIndex i = s.add(Vec3(5.0, 5.0, 1.0));
  s.world.bodies.external_force[i] = Vec3(push, 0.0, -load);
  return s;
}

TEST(SlidingOnWall, HoldsBelowAndSlidesAboveMuTimesLoadPlusCohesion) {
  const double load = 0.5;
  const double threshold = 0.3 * (load + 1.0);  // μ (F_N + F_coh)
  for (const double factor : {kBelow, kAbove}) {
    TinyScene s = sphere_on_wall(load, factor * threshold, 100.0);
    s.run(kSteps);
    const ContactAction a = s.wall_action(0, WallKind::Bottom);
    const double speed = s.world.bodies.velocity[0].norm();
    if (factor < 1.0) {
      EXPECT_LT(speed, kAtRest);
      EXPECT_NEAR(a.tangential_force.x(), -factor * threshold, kForceTol);
    } else {
      EXPECT_GT(speed, kMoving);
      EXPECT_NEAR(a.tangential_force.norm(), threshold, kForceTol);
    }
    EXPECT_NEAR(a.normal_force, load, kForceTol);
  }
}

// With μ_t = 0 the pushed sphere rolls; rolling without slip needs the friction
// f = P I/(I + m R²) = 2P/7, so it slips once 2P/7 exceeds μ S (tests the wall's
// sliding–rolling coupling c ≠ 0 of physics.md §5.2).
TEST(RollingOnWall, RollsWithoutSlipBelowAndSlipsAboveTheNoSlipFriction) {
  const double load = 0.5;
  const double threshold = 0.3 * (load + 1.0);
  for (const double factor : {kBelow, kAbove}) {
    const double push = factor * threshold * 3.5;  // 2P/7 = factor × μ S
    TinyScene s = sphere_on_wall(load, push, 0.0);
    s.run(kSteps);
    const Bodies& b = s.world.bodies;
    // velocity of the contact point: v + ω × (−R e_z)
    const Vec3 slip = b.velocity[0] + b.angular_velocity[0].cross(Vec3(0.0, 0.0, -1.0));
    const ContactAction a = s.wall_action(0, WallKind::Bottom);
    EXPECT_GT(b.velocity[0].x(), kMoving);
    if (factor < 1.0) {
      EXPECT_LT(slip.norm(), kAtRest);
      EXPECT_NEAR(-a.tangential_force.x(), 2.0 * push / 7.0, kForceTol);
    } else {
      EXPECT_GT(slip.norm(), kMoving);
      EXPECT_NEAR(a.tangential_force.norm(), threshold, kForceTol);
    }
  }
}

// A couple about a horizontal axis on a sphere resting on the wall (sliding blocked by a
// large μ): it holds iff T ≤ μ_t (F_N + F_coh) r_eff with r_eff = R at a wall.
TEST(RollingOnWall, HoldsBelowAndRollsAboveTheRollingThreshold) {
  const double load = 0.5;
  const double mu_roll = 0.2;
  const double threshold = mu_roll * (load + 1.0) * 1.0;
  for (const double factor : {kBelow, kAbove}) {
    TinyScene s = sphere_on_wall(load, 0.0, mu_roll);
    s.settings.laws.walls.mu = 100.0;
    s.world.bodies.external_torque[0] = Vec3(0.0, factor * threshold, 0.0);
    s.run(kSteps);
    const ContactAction a = s.wall_action(0, WallKind::Bottom);
    const double spin = s.world.bodies.angular_velocity[0].norm();
    if (factor < 1.0) {
      EXPECT_LT(spin, kAtRest);
    } else {
      EXPECT_GT(spin, kMoving);
      EXPECT_NEAR(a.rolling_torque.norm(), threshold, kForceTol);
    }
  }
}

// Two free equal spheres in a cohesive, unloaded contact (S = F_coh) along x, opposite
// couples ±T. Counter-rotation keeps the contact point at rest, so only one mode works.
TinyScene twisted_pair(const Vec3& axis, double torque) {
  TinyScene s(20.0, 20.0);
  const BodyIndex a = s.add(Vec3(5.0, 5.0, 5.0));
  const BodyIndex b = s.add(Vec3(7.0, 5.0, 5.0));
  s.world.bodies.external_torque[a] = torque * axis;
  s.world.bodies.external_torque[b] = -torque * axis;
  return s;
}

TEST(RollingBetweenSpheres, HoldsBelowAndRollsAboveMuRollCohesionReff) {
  const double mu_roll = 0.4;
  const double threshold = mu_roll * 1.0 * 0.5;  // μ_t F_coh r_eff, r_eff = R/2
  for (const double factor : {kBelow, kAbove}) {
    TinyScene s = twisted_pair(Vec3::UnitY(), factor * threshold);
    s.settings.laws.spheres.mu_roll = mu_roll;
    s.run(kSteps);
    const double spin =
        (s.world.bodies.angular_velocity[1] - s.world.bodies.angular_velocity[0]).norm();
    const ContactAction a = s.pair_action(0, 1);
    if (factor < 1.0) {
      EXPECT_LT(spin, kAtRest);
      EXPECT_NEAR(a.rolling_torque.norm(), factor * threshold, kForceTol);
    } else {
      EXPECT_GT(spin, kMoving);
      EXPECT_NEAR(a.rolling_torque.norm(), threshold, kForceTol);
    }
    EXPECT_NEAR(a.twisting_torque, 0.0, kForceTol);
  }
}

TEST(TorsionBetweenSpheres, HoldsBelowAndTwistsAboveMuTwistCohesionReff) {
  const double mu_twist = 0.4;
  const double threshold = mu_twist * 1.0 * 0.5;  // μ_n F_coh r_eff
  for (const double factor : {kBelow, kAbove}) {
    TinyScene s = twisted_pair(Vec3::UnitX(), factor * threshold);  // about n
    s.settings.laws.spheres.mu_twist = mu_twist;
    s.run(kSteps);
    const double spin =
        (s.world.bodies.angular_velocity[1] - s.world.bodies.angular_velocity[0]).norm();
    const ContactAction a = s.pair_action(0, 1);
    if (factor < 1.0) {
      EXPECT_LT(spin, kAtRest);
    } else {
      EXPECT_GT(spin, kMoving);
    }
    EXPECT_NEAR(std::abs(a.twisting_torque), std::min(factor, 1.0) * threshold, kForceTol);
    EXPECT_NEAR(a.rolling_torque.norm(), 0.0, kForceTol);
  }
}

// Sliding between two spheres with an unloaded cohesive contact: shear forces ±P at the
// centres along y would also make the pair spin as a whole; opposite couples cancel that
// so the test isolates sliding: P ≤ μ F_coh holds, above it slides.
TEST(SlidingBetweenSpheres, HoldsBelowAndSlidesAboveMuTimesCohesion) {
  const double threshold = 0.3 * 1.0;
  for (const double factor : {kBelow, kAbove}) {
    TinyScene s(20.0, 20.0);
    s.settings.laws.spheres.mu_roll = 100.0;  // rolling held: only sliding can give way
    const BodyIndex a = s.add(Vec3(5.0, 5.0, 5.0));
    const BodyIndex b = s.add(Vec3(7.0, 5.0, 5.0));
    const double push = factor * threshold;
    Bodies& bodies = s.world.bodies;
    bodies.external_force[a] = Vec3(0.0, -push, 0.0);
    bodies.external_force[b] = Vec3(0.0, push, 0.0);
    // the shear couple P × 2R about z, cancelled by couples on each sphere
    bodies.external_torque[a] = Vec3(0.0, 0.0, -push);
    bodies.external_torque[b] = Vec3(0.0, 0.0, -push);
    s.run(kSteps);
    const double slip = (bodies.velocity[b] - bodies.velocity[a]).norm();
    const ContactAction action = s.pair_action(a, b);
    if (factor < 1.0) {
      EXPECT_LT(slip, kAtRest);
    } else {
      EXPECT_GT(slip, kMoving);
    }
    // sliding pairs also spin and separate slightly: the threshold is μ (R_n + F_coh)
    const double limit = 0.3 * (action.normal_force + 1.0);
    EXPECT_NEAR(action.tangential_force.norm(), std::min(factor * threshold, limit), kForceTol);
  }
}

}  // namespace
}  // namespace cdpowder::testing
