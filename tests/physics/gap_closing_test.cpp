// The approach target of an open gap (physics.md §5.4 step 1, UK03 eq. 33): a contact may
// close a gap g > 0 within one step, at speed g/Δt, and no faster. Gaps below the touching
// dead band (1e-6 R, solver/build.cpp) count as closed: round-off gaps in a loop of
// sticking contacts otherwise make the normal constraints inconsistent and the NLGS drifts.
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

namespace cdpowder::testing {
namespace {

constexpr double kDt = 0.01;  // Δt of TinyScene [t0]

/// Two unit spheres side by side along x with surface gap `gap`, at rest, one step.
PairProblem pair_after_one_step(double gap) {
  TinyScene s(10.0, 10.0);
  s.add(Vec3(2.0, 5.0, 5.0));
  s.add(Vec3(4.0 + gap, 5.0, 5.0));
  s.run(1);
  EXPECT_EQ(s.work.contacts.pairs.size(), 1U);
  return s.work.contacts.pairs.front();
}

TEST(GapClosing, AnOpenGapMayCloseWithinOneStep) {
  const double gap = 1e-3;  // within the cohesion range 0.01
  const PairProblem p = pair_after_one_step(gap);
  EXPECT_NEAR(p.gap, gap, 1e-12);
  EXPECT_NEAR(p.gap_rate, gap / kDt, 1e-9);
}

TEST(GapClosing, ARoundOffGapCountsAsTouching) {
  EXPECT_EQ(pair_after_one_step(3e-10).gap_rate, 0.0);  // as found in a capped compaction step
  EXPECT_EQ(pair_after_one_step(0.95e-6).gap_rate, 0.0);
  EXPECT_GT(pair_after_one_step(1.05e-6).gap_rate, 0.0);
}

TEST(GapClosing, CohesiveSpheresAtAGapAttractAndClose) {
  // two free spheres 1e-3 apart within the cohesion range: the attraction F_coh closes the
  // gap, after which they stay together at rest (perfectly inelastic)
  TinyScene s(10.0, 10.0);
  const BodyIndex a = s.add(Vec3(2.0, 5.0, 5.0));
  const BodyIndex b = s.add(Vec3(4.001, 5.0, 5.0));
  s.run(200);
  const double distance = (s.world.bodies.position[b] - s.world.bodies.position[a]).norm();
  EXPECT_NEAR(distance, 2.0, 1e-8);
  EXPECT_LT(s.world.bodies.velocity[a].norm(), 1e-9);
}

}  // namespace
}  // namespace cdpowder::testing
