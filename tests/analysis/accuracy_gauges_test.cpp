// The accuracy gauges of physics.md §17 and §6.4 on cases with known answers: the largest
// net force on a sphere (zero in a static packing, the applied load in free flight) and the
// opening speed of cohesive contacts (zero while a pair holds, the relative speed once a
// pulled pair opens), measured before integration exactly as on the World after it.
#include "cdpowder/analysis/cohesive_opening.hpp"
#include "cdpowder/analysis/step_diagnostics.hpp"
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

/// The opening gauges as stage 5 measured them before they moved ahead of integrate():
/// from the World's velocities after the step.
CohesiveOpening opening_after_integration(const TinyScene& scene) {
  const Bodies& bodies = scene.world.bodies;
  const Contacts& contacts = scene.work.contacts;
  const double dt = scene.settings.solver.dt;
  CohesiveOpening out;
  const auto track = [&](double speed, double range) {
    out.speed = std::max(out.speed, speed);
    out.per_range = std::max(out.per_range, speed * dt / range);
  };
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    if (contacts.pair_cohesive[k] == 0) continue;
    track((bodies.velocity[p.b] - bodies.velocity[p.a]).dot(p.normal),
          scene.settings.laws.spheres.cohesion_range);
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    if (contacts.wall_cohesive[k] == 0) continue;
    const double wall_speed = w.wall == WallKind::Piston ? scene.world.walls.piston.velocity : 0.0;
    track((bodies.velocity[w.sphere].z() - wall_speed) * w.normal.z(),
          scene.settings.laws.walls.cohesion_range);
  }
  return out;
}

/// Three steps of `scene`: the gauges of each equal those measured after integration.
void expect_opening_as_after_integration(TinyScene& scene) {
  for (int k = 0; k < 3; ++k) {
    const StepReport report = scene.run(1);
    const CohesiveOpening reference = opening_after_integration(scene);
    EXPECT_GT(reference.speed, 0.0);
    EXPECT_EQ(report.diagnostics.max_cohesive_opening_speed, reference.speed);
    EXPECT_EQ(report.diagnostics.max_cohesive_opening_per_range, reference.per_range);
  }
}

TEST(AccuracyGauges, OpeningMeasuredBeforeIntegrationIsTheOpeningAfterItToTheLastBit) {
  // a free sphere pulled off a fixed one that has a velocity of its own (integrate leaves
  // it, and v* of a fixed sphere is zero)
  TinyScene pair(30.0, 30.0);
  pair.add(Vec3(5.0, 5.0, 5.0), 1.0, true);
  pair.add(Vec3(7.0, 5.0, 5.0));
  pair.world.bodies.velocity[0] = Vec3(-0.3, 0.02, 0.0);
  pair.world.bodies.external_force[1] = Vec3(1.5, 0.2, 0.0);
  expect_opening_as_after_integration(pair);

  // a sphere pulled off a moving piston
  TinyScene piston(30.0, 30.0);
  piston.world.walls.piston.enabled = true;
  piston.world.walls.piston.height = 10.0;
  piston.world.walls.piston.velocity = 0.05;
  piston.world.walls.piston.force = 0.2;
  piston.add(Vec3(15.0, 15.0, 9.0));
  piston.world.bodies.external_force[0] = Vec3(0.0, 0.0, -1.7);
  expect_opening_as_after_integration(piston);
}

}  // namespace
}  // namespace cdpowder::testing
