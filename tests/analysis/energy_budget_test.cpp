// The energy budget of physics.md §17, "The energy budget" (analysis/energy_budget.hpp,
// RunSummary::Energy): bonds counted by key against the step before, the cohesion's potential
// energy, and a budget that closes on a known answer and survives a state file.
#include "cdpowder/analysis/energy_budget.hpp"

#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/run/state_file.hpp"
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cdpowder::testing {
namespace {

PairProblem pair(BodyIndex a, BodyIndex b, double gap = 0.0, double cohesion = 1.0) {
  PairProblem p;
  p.a = a;
  p.b = b;
  p.gap = gap;
  p.cohesion = cohesion;
  return p;
}

WallProblem wall(WallKind kind, BodyIndex sphere, double gap = 0.0, double cohesion = 1.0) {
  WallProblem w;
  w.wall = kind;
  w.sphere = sphere;
  w.gap = gap;
  w.cohesion = cohesion;
  return w;
}

/// `contacts` as the warm-start cache holds them after their step (ActionCache::last).
KeyedContacts as_cached(Contacts contacts) {
  contacts.pair_actions.resize(contacts.pairs.size());
  contacts.wall_actions.resize(contacts.walls.size());
  ActionCache cache;
  cache.take(contacts);
  return cache.last();
}

TEST(BondChanges, CountsBondsFormedAndBrokenByKeyIncludingContactsThatLeftTheList) {
  Contacts last;
  last.pairs = {pair(0, 1), pair(0, 2), pair(1, 3), pair(2, 5)};
  last.pair_cohesive = {1, 1, 0, 1};
  last.walls = {wall(WallKind::Bottom, 4), wall(WallKind::Piston, 2)};
  last.wall_cohesive = {1, 0};
  Contacts now;
  // (0,1) stays a bond, (0,2) opens, (1,3) becomes one, (2,4) is new, (2,5) left the list
  now.pairs = {pair(0, 1), pair(0, 2), pair(1, 3), pair(2, 4)};
  now.pair_cohesive = {1, 0, 1, 1};
  // the bottom bond left the list; the piston contact bonds
  now.walls = {wall(WallKind::Piston, 2)};
  now.wall_cohesive = {1};
  const BondChanges c = bond_changes(as_cached(last), now);
  EXPECT_EQ(c.pairs_formed, 2);
  EXPECT_EQ(c.pairs_broken, 2);
  EXPECT_EQ(c.walls_formed, 1);
  EXPECT_EQ(c.walls_broken, 1);
  EXPECT_EQ(bond_changes(as_cached(now), now).formed() + bond_changes(as_cached(now), now).broken(),
            0);
  EXPECT_EQ(bond_changes(KeyedContacts{}, now).formed(), 4);  // an empty cache: all formed
}

TEST(CohesiveEnergy, IsMinusCohesionTimesTheRangeLeftOverTheBonds) {
  ContactLaws laws;
  laws.spheres.cohesion_range = 0.01;
  laws.walls.cohesion_range = 0.02;
  Contacts c;
  c.pairs = {pair(0, 1, 0.004, 1.0), pair(0, 2, -0.001, 2.0), pair(1, 2, 0.0, 0.0)};
  c.pair_cohesive = {1, 1, 0};
  c.walls = {wall(WallKind::Bottom, 0, 0.005, 3.0)};
  c.wall_cohesive = {1};
  // −(1 × 0.006) − (2 × 0.01, an overlap counts as touching) − (3 × 0.015)
  EXPECT_NEAR(cohesive_energy(c, laws), -(0.006 + 0.02 + 0.045), 1e-15);
}

// A sphere hanging under a fixed one, its weight m g = 1.5 F_coh: the bond opens, pulls with
// F_coh over d_coh and breaks. Rigid spheres pulled apart dissipate nothing, so the budget
// closes with W_gravity = ΔK + F_coh d_coh (one bond broken), up to the opening of one step
// and the first-order integrator's O(F v Δt) a step (as in cohesion_test.cpp).
TinyScene hanging_sphere() {
  TinyScene s(30.0, 30.0);
  s.add(Vec3(5.0, 5.0, 10.0), 1.0, /*fixed=*/true);
  s.add(Vec3(5.0, 5.0, 8.0));
  const double mass = 4.0 / 3.0 * std::numbers::pi;
  s.world.gravity = Vec3(0.0, 0.0, -1.5 / mass);
  s.settings.solver.dt = 1e-3;
  return s;
}

TEST(EnergyBudget, ABondPulledOpenByGravityCostsCohesionTimesRangeAndNothingIsDissipated) {
  TinyScene s = hanging_sphere();
  RunConfig run;
  run.duration = 2.0;
  const RunResult result = run_simulation(s.world, s.work, s.settings, run, {});
  const double fall = 8.0 - s.world.bodies.position[1].z();
  ASSERT_GT(fall, 0.05);  // beyond d_coh = 0.01: broken
  const RunSummary::Energy e = energy_budget(s.settings.laws, s.world, s.work.contacts, result);
  ASSERT_TRUE(e.complete);
  EXPECT_EQ(e.bonds_broken, 1);
  EXPECT_EQ(e.bonds_formed, 0);
  EXPECT_DOUBLE_EQ(e.breaking_work, 0.01);
  EXPECT_NEAR(e.cohesive_start, -0.01, 1e-15);
  EXPECT_EQ(e.cohesive_end, 0.0);
  EXPECT_NEAR(e.gravity_work, 1.5 * fall, 1e-12);
  EXPECT_EQ(e.piston_work, 0.0);
  const double speed = s.world.bodies.velocity[1].norm();
  const double tolerance = (1.0 + 1.5) * speed * s.settings.solver.dt * 2.0;
  EXPECT_NEAR(e.dissipated, 0.0, tolerance);
}

// The budget of a run continued from its state file is the budget of the run never stopped,
// to the bit; a format-1 file (the benchmarks' fixtures) kept none: unknown.
TEST(EnergyBudget, SurvivesAStateFileToTheBitAndIsUnknownAfterAFormatOneFile) {
  RunConfig run;
  run.duration = 2.0;
  TinyScene whole = hanging_sphere();
  const RunResult uninterrupted = run_simulation(whole.world, whole.work, whole.settings, run, {});
  TinyScene first = hanging_sphere();
  RunState state;
  run_simulation(first.world, first.work, first.settings, run, state, {},
                 [&] { return state.result.steps == 300; });
  TinyScene resumed = hanging_sphere();
  RunState resumed_state;
  restore_run(decode_state(encode_state("", first.world, first.work, state), "memory"), run,
              resumed.settings.solver.dt, resumed.world, resumed.work, resumed_state);
  const RunResult result =
      run_simulation(resumed.world, resumed.work, resumed.settings, run, resumed_state, {});
  const RunSummary::Energy a =
      energy_budget(whole.settings.laws, whole.world, whole.work.contacts, uninterrupted);
  const RunSummary::Energy b =
      energy_budget(resumed.settings.laws, resumed.world, resumed.work.contacts, result);
  EXPECT_EQ(a.bonds_broken, b.bonds_broken);
  EXPECT_EQ(a.bonds_formed, b.bonds_formed);
  EXPECT_EQ(a.dissipated, b.dissipated);
  EXPECT_EQ(a.gravity_work, b.gravity_work);
  EXPECT_EQ(a.cohesive_start, b.cohesive_start);

  const SavedRun old = load_state(std::filesystem::path(CDPOWDER_SOURCE_DIR) /
                                  "bench/fixtures/paper_mid_mu11_t240.cdps");
  EXPECT_EQ(old.format_version, 1U);
  EXPECT_FALSE(old.result.energy_known);
  EXPECT_TRUE(
      std::isnan(energy_budget(ContactLaws{}, old.world, Contacts{}, old.result).dissipated));
}

}  // namespace
}  // namespace cdpowder::testing
