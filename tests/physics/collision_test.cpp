// Free collisions (physics.md §15 item 7): perfectly inelastic contact in two steps,
// conservation of linear and angular momentum, and contact across a periodic boundary.
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cdpowder::testing {
namespace {

// Momentum is exchanged only through equal and opposite impulses: round-off only.
constexpr double kRoundOff = 1e-12;

TEST(HeadOnCollision, ClosesInTheFirstStepAndStopsApproachInTheSecond) {
  TinyScene s(30.0, 30.0);
  s.settings.laws.spheres = ContactLaw{0.0, 0.0, 0.0, 0.0, 0.0};  // μ = 0, no cohesion
  s.add(Vec3(5.0, 5.0, 5.0));
  s.add(Vec3(7.005, 5.0, 5.0));  // gap 0.005 < |V_n| Δt = 0.01
  s.world.bodies.velocity[0] = Vec3(0.5, 0.0, 0.0);
  s.world.bodies.velocity[1] = Vec3(-0.5, 0.0, 0.0);
  const Vec3 p0 = total_momentum(s.world.bodies);
  s.run(1);
  const Bodies& b = s.world.bodies;
  EXPECT_NEAR((b.position[1] - b.position[0]).norm(), 2.0, kRoundOff);  // touching, no overlap
  s.run(1);
  EXPECT_NEAR(b.velocity[1].x() - b.velocity[0].x(), 0.0, kRoundOff);  // stuck together
  EXPECT_LT((total_momentum(b) - p0).norm(), kRoundOff);
}

// Angular momentum drift of a colliding, then co-rotating cohesive pair after 3 t0.
double angular_momentum_drift(double dt, double& relative_to) {
  TinyScene s(30.0, 30.0);
  s.settings.solver.dt = dt;
  s.settings.laws.spheres = ContactLaw{0.3, 0.2, 0.1, 1.0, 0.01};
  s.add(Vec3(5.0, 5.0, 5.0), 1.0);
  s.add(Vec3(7.5, 5.5, 5.2), 0.7);
  Bodies& b = s.world.bodies;
  b.velocity[0] = Vec3(0.3, 0.05, 0.0);
  b.velocity[1] = Vec3(-0.4, -0.1, 0.02);
  b.angular_velocity[0] = Vec3(0.1, -0.2, 0.3);
  b.angular_velocity[1] = Vec3(-0.3, 0.2, 0.1);
  const Vec3 l0 = total_angular_momentum(b);
  relative_to = l0.norm();
  s.run(static_cast<int>(std::lround(3.0 / dt)));
  return (total_angular_momentum(b) - l0).norm();
}

// Impulses are equal and opposite and act at one common point, the middle of the gap
// (physics.md §4.2), also in the step in which the gap closes (g ≠ 0, frozen normal): the
// angular momentum about any point is conserved to round-off. (With levers from each centre
// to its own surface the forces acted g apart, and the drift was 3.1e-4 |L0| at Δt = 0.01.)
TEST(ObliqueCollision, ConservesAngularMomentumToRoundOff) {
  constexpr double kRelativeRoundOff = 1e-12;  // 300–600 steps of ≈ 1e-16 each
  for (const double dt : {0.01, 0.005}) {
    double l0 = 0.0;
    const double drift = angular_momentum_drift(dt, l0);
    EXPECT_LT(drift, kRelativeRoundOff * l0) << "dt " << dt << " |L0| " << l0;
  }
}

TEST(ObliqueCollision, ConservesLinearMomentumWithAllLaws) {
  TinyScene s(30.0, 30.0);
  s.settings.laws.spheres = ContactLaw{0.3, 0.2, 0.1, 1.0, 0.01};
  s.add(Vec3(5.0, 5.0, 5.0), 1.0);
  s.add(Vec3(7.5, 5.5, 5.2), 0.7);  // unequal radii: sliding and rolling couple
  Bodies& b = s.world.bodies;
  b.velocity[0] = Vec3(0.3, 0.05, 0.0);
  b.velocity[1] = Vec3(-0.4, -0.1, 0.02);
  b.angular_velocity[0] = Vec3(0.1, -0.2, 0.3);
  b.angular_velocity[1] = Vec3(-0.3, 0.2, 0.1);
  const Vec3 p0 = total_momentum(b);
  for (int k = 0; k < 300; ++k) {
    s.run(1);
    EXPECT_LT((total_momentum(b) - p0).norm(), kRoundOff);
  }
  EXPECT_GT(s.work.contacts.size(), 0U);
}

TEST(PeriodicBoundary, SphereCrossesAndCollidesThroughTheBoundary) {
  TinyScene s(10.0, 10.0);
  s.settings.laws.spheres = ContactLaw{0.0, 0.0, 0.0, 0.0, 0.0};
  s.add(Vec3(8.5, 5.0, 5.0));  // moving +x towards the boundary at x = 10
  s.add(Vec3(1.5, 5.0, 5.0));  // at rest just across it
  Bodies& b = s.world.bodies;
  b.velocity[0] = Vec3(1.0, 0.0, 0.0);
  s.run(200);  // after 1 t0 the gap of 1 R is closed, inelastic: both at 0.5
  EXPECT_NEAR(b.velocity[0].x(), 0.5, kRoundOff);
  EXPECT_NEAR(b.velocity[1].x(), 0.5, kRoundOff);
  for (const Vec3& p : b.position) {
    EXPECT_GE(p.x(), 0.0);
    EXPECT_LT(p.x(), 10.0);
  }
  const Vec3 d = s.world.box.minimum_image(b.position[1] - b.position[0]);
  EXPECT_NEAR(d.norm(), 2.0, 1e-9);
}

}  // namespace
}  // namespace cdpowder::testing
