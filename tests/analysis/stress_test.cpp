// Tests for src/cdpowder/analysis/stress.cpp: single contacts with known stress.
#include "cdpowder/analysis/stress.hpp"

#include <gtest/gtest.h>

namespace cdpowder {
namespace {

TEST(StressTensors, CompressivePairGivesForceTimesBranchOverVolume) {
  Contacts c;
  PairProblem p;
  p.normal = Vec3::UnitZ();
  p.lever_a = p.lever_b = 1.0;
  c.pairs.push_back(p);
  ContactAction a;
  a.normal_force = 2.0;
  a.tangential_force = Vec3(0.5, 0.0, 0.0);
  c.pair_actions.push_back(a);
  c.pair_cohesive.push_back(0);
  const StressTensors s = stress_tensors(c, 10.0);
  // F = (0.5, 0, 2), l = (0, 0, 2): σ_xz = 0.5·2/10, σ_zz = 2·2/10
  EXPECT_DOUBLE_EQ(s.total(2, 2), 0.4);
  EXPECT_DOUBLE_EQ(s.total(0, 2), 0.1);
  EXPECT_DOUBLE_EQ(s.total(2, 0), 0.0);
  EXPECT_EQ(s.compressive, s.total);
  EXPECT_EQ(s.compressive_contacts, 1U);
  EXPECT_EQ(s.tensile_contacts, 0U);
}

TEST(StressTensors, TensilePairAndPistonWallSplitBySign) {
  Contacts c;
  PairProblem p;
  p.normal = Vec3::UnitX();
  p.gap = 0.01;                               // open but still attracting
  p.lever_a = p.lever_b = 1.0 + 0.5 * p.gap;  // R + g/2: to the middle of the gap
  p.cohesion = 1.0;
  c.pairs.push_back(p);
  ContactAction pull;
  pull.normal_force = -1.0;
  c.pair_actions.push_back(pull);
  c.pair_cohesive.push_back(1);
  WallProblem w;
  w.wall = WallKind::Piston;
  w.normal = -Vec3::UnitZ();
  w.radius = 1.0;
  c.walls.push_back(w);
  ContactAction push;
  push.normal_force = 3.0;
  c.wall_actions.push_back(push);
  c.wall_cohesive.push_back(0);
  const StressTensors s = stress_tensors(c, 2.0);
  EXPECT_DOUBLE_EQ(s.tensile(0, 0), -1.0 * 2.01 / 2.0);
  EXPECT_DOUBLE_EQ(s.compressive(2, 2), 3.0 * 1.0 / 2.0);  // (−3 e_z) ⊗ (−1 e_z) / V
  EXPECT_EQ(s.total, s.tensile + s.compressive);
  EXPECT_EQ(s.tensile_contacts, 1U);
  EXPECT_EQ(s.compressive_contacts, 1U);
}

TEST(StressTensors, NonCohesiveOpenCandidateCountsForNothing) {
  Contacts c;
  c.pairs.push_back(PairProblem{});
  c.pair_actions.push_back(ContactAction{});
  c.pair_cohesive.push_back(0);
  const StressTensors s = stress_tensors(c, 1.0);
  EXPECT_EQ(s.compressive_contacts + s.tensile_contacts, 0U);
}

}  // namespace
}  // namespace cdpowder
