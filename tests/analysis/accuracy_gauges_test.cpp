// The accuracy gauges of physics.md §17 and §6.4 on cases with known answers: the largest
// net force on a sphere (zero in a static packing, the applied load in free flight) and the
// opening speed of cohesive contacts (zero while a pair holds, the relative speed once a
// pulled pair opens).
#include "cdpowder/analysis/step_diagnostics.hpp"
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace cdpowder::testing {
namespace {

TEST(AccuracyGauges, NetForceIsTheLoadInFreeFlightAndZeroInAStaticColumn) {
  TinyScene free_flight(10.0, 10.0);
  free_flight.add(Vec3(5.0, 5.0, 5.0));
  free_flight.world.bodies.external_force[0] = Vec3(0.3, 0.0, -0.4);  // |F| = 0.5
  EXPECT_NEAR(free_flight.run(1).diagnostics.max_net_force, 0.5, 1e-12);

  // three spheres on the bottom wall under a loaded piston: at rest, every sphere balanced
  TinyScene column(5.0, 5.0);
  column.world.walls.bottom.enabled = true;
  column.world.walls.piston.enabled = true;
  column.world.walls.piston.mass = 1000.0;
  column.world.walls.piston.force = 0.7;
  for (int k = 0; k < 3; ++k) column.add(Vec3(2.5, 2.5, 1.0 + 2.0 * k));
  column.world.walls.piston.height = 6.0;
  EXPECT_LT(column.run(20).diagnostics.max_net_force, 1e-6);
}

TEST(AccuracyGauges, CohesiveOpeningSpeedIsZeroWhileHeldAndTheRelativeSpeedOnceOpen) {
  // pulled with 0.95 F_coh: the pair holds, nothing opens
  TinyScene held(30.0, 30.0);
  held.add(Vec3(5.0, 5.0, 5.0));
  held.add(Vec3(7.0, 5.0, 5.0));
  held.world.bodies.external_force[0] = Vec3(-0.95, 0.0, 0.0);
  held.world.bodies.external_force[1] = Vec3(0.95, 0.0, 0.0);
  EXPECT_LT(held.run(10).diagnostics.max_cohesive_opening_speed, 1e-9);

  // pulled with 1.5 F_coh: each sphere accelerates with (1.5 − 1)/m while cohesive
  TinyScene pulled(30.0, 30.0);
  pulled.add(Vec3(5.0, 5.0, 5.0));
  pulled.add(Vec3(7.0, 5.0, 5.0));
  pulled.world.bodies.external_force[0] = Vec3(-1.5, 0.0, 0.0);
  pulled.world.bodies.external_force[1] = Vec3(1.5, 0.0, 0.0);
  const StepReport report = pulled.run(3);
  const double relative = pulled.world.bodies.velocity[1].x() - pulled.world.bodies.velocity[0].x();
  const double mass = 4.0 / 3.0 * std::numbers::pi;
  EXPECT_GT(relative, 0.0);
  EXPECT_NEAR(report.diagnostics.max_cohesive_opening_speed, relative, 1e-12);
  EXPECT_NEAR(report.diagnostics.max_cohesive_opening_per_range,
              relative * pulled.settings.solver.dt / pulled.settings.laws.spheres.cohesion_range,
              1e-12);
  EXPECT_NEAR(relative, 2.0 * 3.0 * pulled.settings.solver.dt * 0.5 / mass, 1e-9);
}

}  // namespace
}  // namespace cdpowder::testing
