// The cohesion law of physics.md §6 through whole steps (§15 item 2): a pair pulled
// with less than F_coh holds with R_n = −F_ext; pulled harder it opens, feels −F_coh
// while the gap is within d_coh, then breaks; the work to break is F_coh d_coh.
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace cdpowder::testing {
namespace {

constexpr double kForceTol = 1e-6;  // converged forces (solver tolerance 1e-10) [F_coh]

// Two touching spheres along x, pulled apart by ±F at their centres.
TinyScene pulled_pair(double pull) {
  TinyScene s(30.0, 30.0);
  s.add(Vec3(5.0, 5.0, 5.0));
  s.add(Vec3(7.0, 5.0, 5.0));
  s.world.bodies.external_force[0] = Vec3(-pull, 0.0, 0.0);
  s.world.bodies.external_force[1] = Vec3(pull, 0.0, 0.0);
  return s;
}

double gap(const TinyScene& s) {
  return (s.world.bodies.position[1] - s.world.bodies.position[0]).norm() - 2.0;
}

TEST(CohesivePair, HoldsWhenPulledJustBelowCohesionForce) {
  TinyScene s = pulled_pair(0.95);
  s.run(100);
  EXPECT_NEAR(s.pair_action(0, 1).normal_force, -0.95, kForceTol);
  EXPECT_LT(std::abs(gap(s)), 1e-12);
}

TEST(CohesivePair, OpensWhenPulledJustAboveCohesionForceAndPullsWithFcohWithinRange) {
  TinyScene s = pulled_pair(1.05);
  s.settings.laws.spheres.cohesion_range = 0.01;
  bool saw_open_attracting = false;
  for (int k = 0; k < 2000 && gap(s) < 0.02; ++k) {
    const double gap_before = gap(s);  // the law is decided on the start-of-step gap
    s.run(1);
    const double R_n = s.pair_action(0, 1).normal_force;
    if (gap_before > 1e-9 && gap_before <= 0.01) {
      EXPECT_DOUBLE_EQ(R_n, -1.0) << "gap " << gap_before;
      saw_open_attracting = true;
    }
    if (gap_before > 0.01) {
      EXPECT_EQ(R_n, 0.0) << "gap " << gap_before;
    }
  }
  EXPECT_TRUE(saw_open_attracting);
  EXPECT_GT(gap(s), 0.01);
}

// Kinetic energy after breaking = F_ext s − F_coh d_coh (s = total opening), up to the
// opening of one step, F_coh |V_n| Δt, and the first-order integrator's O(F v Δt) per step.
TEST(CohesivePair, BreakingCostsCohesionForceTimesRange) {
  const double pull = 1.5;
  const double range = 0.01;
  TinyScene s = pulled_pair(pull);
  s.settings.laws.spheres.cohesion_range = range;
  s.settings.solver.dt = 1e-3;
  while (gap(s) < 0.05) s.run(1);
  const Bodies& b = s.world.bodies;
  const double m = 4.0 / 3.0 * std::numbers::pi;
  const double kinetic = 0.5 * m * (b.velocity[0].squaredNorm() + b.velocity[1].squaredNorm());
  const double expected = pull * gap(s) - 1.0 * range;
  const double opening_speed = (b.velocity[1] - b.velocity[0]).norm();
  const double tolerance = (1.0 + pull) * opening_speed * s.settings.solver.dt * 2.0;
  EXPECT_NEAR(kinetic, expected, tolerance);
  EXPECT_GT(kinetic, pull * gap(s) - 1.0 * range - tolerance);  // it did cost the energy
  EXPECT_LT(kinetic, pull * gap(s));
}

// After opening within the range, pushing back closes it into an ordinary closed cohesive
// contact (no special treatment, §6.2).
TEST(CohesivePair, ReclosesWhenPushedBackWithinRange) {
  TinyScene s = pulled_pair(1.05);
  s.settings.laws.spheres.cohesion_range = 0.05;
  while (gap(s) < 0.005) s.run(1);
  s.world.bodies.external_force[0] = Vec3(0.5, 0.0, 0.0);  // now pushing together
  s.world.bodies.external_force[1] = Vec3(-0.5, 0.0, 0.0);
  s.run(400);
  EXPECT_LT(std::abs(gap(s)), 1e-9);
  // closed, pushed with 0.5 plus the attraction of nothing: R_n = +0.5
  EXPECT_NEAR(s.pair_action(0, 1).normal_force, 0.5, kForceTol);
}

// A pair that never touched but sits within d_coh: the graph rule attracts it, the
// history rule does not (§6.2).
TEST(CohesionRule, GraphAttractsAGapWithinRangeAndHistoryDoesNot) {
  for (const CohesionRule rule : {CohesionRule::Graph, CohesionRule::History}) {
    TinyScene s(30.0, 30.0);
    s.settings.laws.cohesion_rule = rule;
    s.settings.laws.spheres.cohesion_range = 0.05;
    s.add(Vec3(5.0, 5.0, 5.0));
    s.add(Vec3(7.02, 5.0, 5.0));
    s.run(1);
    const double R_n = s.pair_action(0, 1).normal_force;
    if (rule == CohesionRule::Graph) {
      EXPECT_DOUBLE_EQ(R_n, -1.0);
    } else {
      EXPECT_EQ(R_n, 0.0);
    }
  }
}

// Touching is touching for both rules: an exactly touching pair whose gap came out of
// round-off slightly positive (as in a deposit, |g| ~ 1e-15) is bonded under the history
// rule too, and holds against a pull below F_coh.
TEST(CohesionRule, HistoryBondsAPairTouchingUpToRoundOff) {
  for (const CohesionRule rule : {CohesionRule::Graph, CohesionRule::History}) {
    for (const double round_off : {-1e-15, 1e-15, 1e-9}) {
      TinyScene s = pulled_pair(0.5);
      s.settings.laws.cohesion_rule = rule;
      s.world.bodies.position[1].x() += round_off;
      s.run(1);
      EXPECT_NEAR(s.pair_action(0, 1).normal_force, -0.5, kForceTol) << round_off;
      EXPECT_LT(gap(s), 1e-6);
    }
  }
}

}  // namespace
}  // namespace cdpowder::testing
