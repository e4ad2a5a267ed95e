// Faults (run/run_fault.hpp): a state no physical run reaches is found the step it
// appears, named with the quantity, the sphere and the step, and ends the run; and the
// piston's weight is part of its load, so a compaction under gravity blocks.
#include "cdpowder/run/run_fault.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "support/tiny_world.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace cdpowder::testing {
namespace {

using ::testing::HasSubstr;

// Two spheres side by side on the bottom wall under the piston, at rest.
TinyScene two_under_a_piston() {
  TinyScene s(6.0, 6.0);
  s.world.walls.bottom.enabled = true;
  s.world.walls.piston.enabled = true;
  s.world.walls.piston.force = 0.01;
  s.add(Vec3(1.5, 3.0, 1.0));
  s.add(Vec3(3.5, 3.0, 1.0));
  s.world.walls.piston.height = 2.0;
  return s;
}

FaultLimits limits_of(const World& world) {
  return FaultLimits{0.1, grain_volume(world.bodies)};
}

std::optional<RunFault> fault_after_a_step(TinyScene& s) {
  const StepReport report = s.run(1);
  return find_fault(s.world, s.work.contacts, report.diagnostics, limits_of(s.world));
}

TEST(RunFault, ARestingPackingHasNone) {
  TinyScene s = two_under_a_piston();
  EXPECT_FALSE(fault_after_a_step(s).has_value());
}

TEST(RunFault, ANonFiniteVelocityNamesTheSphereAndTheStep) {
  TinyScene s = two_under_a_piston();
  s.run(3);
  s.world.bodies.velocity[1].y() = std::numeric_limits<double>::quiet_NaN();
  const std::optional<RunFault> f =
      find_fault(s.world, s.work.contacts, StepDiagnostics{}, limits_of(s.world));
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->quantity, "velocity");
  EXPECT_EQ(f->body, 1);
  EXPECT_EQ(f->step, 3);
  EXPECT_THAT(f->message, HasSubstr("velocity of sphere 1 is not finite"));
  EXPECT_THAT(f->message, HasSubstr("at step 3"));
}

// A value turned non-finite by a step ends the run after that step. (A step is never given
// a non-finite input: debug builds assert on it, detect_contacts.cpp; so the test spoils the
// piston's velocity after step 3, where a failing step would have left it, through the
// observer, which runs before the check. The spheres' finiteness is measured by integrate()
// on its pass and trusted by the check: integrate_test covers it, and the next test the
// search for the sphere when the step has not vouched for them.)
TEST(RunFault, ANonFiniteValueStopsTheRunAfterItsStep) {
  TinyScene s = two_under_a_piston();
  RunConfig run;
  run.duration = 1.0;  // 100 steps
  const RunResult result = run_simulation(
      s.world, s.work, s.settings, run, [&s](const World& world, const StepReport&, double) {
        if (world.step == 3) {
          s.world.walls.piston.velocity = std::numeric_limits<double>::infinity();
        }
      });
  ASSERT_TRUE(result.fault.has_value());
  EXPECT_EQ(result.steps, 3);
  EXPECT_EQ(result.fault->step, 3);
  EXPECT_EQ(result.fault->body, -1);
  EXPECT_EQ(result.fault->quantity, "piston");
  EXPECT_FALSE(result.blocked);
  EXPECT_FALSE(result.interrupted);
}

// The spheres are searched when the step's diagnostics have not found them finite; when
// they have (integrate's pass, every step of a run), the check trusts them.
TEST(RunFault, SpheresAreSearchedWhenTheStepHasNotFoundThemFinite) {
  TinyScene s = two_under_a_piston();
  StepReport report = s.run(3);
  EXPECT_TRUE(report.diagnostics.spheres_finite);
  s.world.bodies.angular_velocity[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(
      find_fault(s.world, s.work.contacts, report.diagnostics, limits_of(s.world)).has_value());
  report.diagnostics.spheres_finite = false;
  const std::optional<RunFault> f =
      find_fault(s.world, s.work.contacts, report.diagnostics, limits_of(s.world));
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->quantity, "angular velocity");
  EXPECT_EQ(f->body, 0);
}

// Just below the overlap bound nothing happens; just above, the pair is named.
TEST(RunFault, AnOverlapBeyondTheBoundNamesThePair) {
  TinyScene s = two_under_a_piston();
  const StepReport report = s.run(1);
  s.world.bodies.position[1].x() = 1.5 + 2.0 - 0.2;  // overlaps sphere 0 by 0.2 R
  StepDiagnostics d = report.diagnostics;
  FaultLimits limits = limits_of(s.world);
  d.max_overlap = 0.2;
  limits.max_overlap = 0.2 + 1e-12;
  EXPECT_FALSE(find_fault(s.world, s.work.contacts, d, limits).has_value());
  limits.max_overlap = 0.2 - 1e-12;
  const std::optional<RunFault> f = find_fault(s.world, s.work.contacts, d, limits);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->quantity, "overlap");
  EXPECT_EQ(f->body, 0);
  EXPECT_EQ(f->other, 1);
  EXPECT_NEAR(f->value, 0.2, 1e-12);
  EXPECT_THAT(f->message, HasSubstr("sphere 0 overlaps sphere 1 by 0.2 R"));
  // the value named is the one the step's measure found, to the bit
  StepDiagnostics measured;
  measure_contacts(s.world, s.work.contacts, measured);
  EXPECT_EQ(find_fault(s.world, s.work.contacts, measured, limits)->value, measured.max_overlap);
}

TEST(RunFault, APistonThroughTheWallOrBelowTheGrainsVolumeIsAFault) {
  TinyScene s = two_under_a_piston();
  const StepReport report = s.run(1);
  const FaultLimits limits{1e300, grain_volume(s.world.bodies)};  // no overlap fault
  s.world.walls.piston.height = -0.5;
  std::optional<RunFault> f = find_fault(s.world, s.work.contacts, report.diagnostics, limits);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->quantity, "piston height");
  // E = 1 − V_grains/(A Z_P) ≤ 0 just below Z_P = V_grains / A, not above it
  const double z_full = limits.grain_volume / s.world.box.area();
  s.world.walls.piston.height = z_full * (1.0 + 1e-9);
  EXPECT_FALSE(find_fault(s.world, s.work.contacts, report.diagnostics, limits).has_value());
  s.world.walls.piston.height = z_full * (1.0 - 1e-9);
  f = find_fault(s.world, s.work.contacts, report.diagnostics, limits);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->quantity, "porosity");
}

// Under gravity the spheres carry the push F and the piston's weight M_P g: the force
// balance is judged against both (once measured: a compaction under gravity never blocked,
// its contact force 0.9225 = F 0.5625 + M_P g 0.36 against F alone).
TEST(RunFault, APistonUnderGravityIsBalancedByItsPushAndItsWeight) {
  TinyScene s = two_under_a_piston();
  s.world.gravity = Vec3(0.0, 0.0, -0.01);
  s.world.walls.piston.mass = 50.0;
  EXPECT_DOUBLE_EQ(piston_load(s.world), 0.01 + 50.0 * 0.01);
  const StepReport report = s.run(200);
  EXPECT_NEAR(report.diagnostics.piston_contact_force, piston_load(s.world), 1e-6);
  EXPECT_LT(report.diagnostics.piston_imbalance, 1e-6);
}

}  // namespace
}  // namespace cdpowder::testing
