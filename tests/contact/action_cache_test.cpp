// Tests for src/cdpowder/contact/action_cache.cpp: the warm start's merge join (physics.md
// §7.4) returns exactly the stored entries for ascending keys and nothing for missing ones,
// and the contact lists a real step produces are in the order the merge requires.
#include "cdpowder/contact/action_cache.hpp"

#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace cdpowder::testing {
namespace {

ContactAction action_with(double normal_force) {
  ContactAction action;
  action.normal_force = normal_force;
  action.tangential_force = Vec3(0.0, 0.1 * normal_force, 0.0);
  return action;
}

void add_pair(Contacts& c, BodyIndex a, BodyIndex b, const ContactAction& action, bool cohesive) {
  PairProblem p;
  p.a = a;
  p.b = b;
  c.pairs.push_back(p);
  c.pair_actions.push_back(action);
  c.pair_cohesive.push_back(cohesive ? 1 : 0);
}

void add_wall(Contacts& c, WallKind wall, BodyIndex sphere, const ContactAction& action,
              bool cohesive) {
  WallProblem w;
  w.wall = wall;
  w.sphere = sphere;
  c.walls.push_back(w);
  c.wall_actions.push_back(action);
  c.wall_cohesive.push_back(cohesive ? 1 : 0);
}

void expect_entry(LastAction found, std::uint64_t key, const ContactAction& action, bool cohesive) {
  ASSERT_TRUE(found) << "key " << key;
  EXPECT_EQ(found.action->normal_force, action.normal_force) << "key " << key;
  EXPECT_EQ(found.action->tangential_force, action.tangential_force) << "key " << key;
  EXPECT_EQ(found.cohesive, cohesive) << "key " << key;
}

TEST(ActionCache, AscendingLookupsReturnExactlyTheStoredEntries) {
  Contacts c;
  add_pair(c, 0, 1, action_with(1.0), false);
  add_pair(c, 0, 5, ContactAction{}, false);  // zero force, not cohesive: carries nothing
  add_pair(c, 0, 7, ContactAction{}, true);   // zero force but cohesive: carries over
  add_pair(c, 2, 3, action_with(-0.5), true);
  add_pair(c, 7, 9, action_with(2.0), false);
  add_wall(c, WallKind::Bottom, 1, action_with(3.0), false);
  add_wall(c, WallKind::Bottom, 4, ContactAction{}, false);  // carries nothing
  add_wall(c, WallKind::Piston, 0, action_with(4.0), true);
  add_wall(c, WallKind::Piston, 4, action_with(5.0), false);
  ActionCache cache;
  cache.store(c);
  EXPECT_EQ(carried_pairs(cache.last()).size() + carried_walls(cache.last()).size(), 7U);

  // every key of a larger set, ascending: missing keys interleaved, before and after all
  std::size_t pairs = 0;
  std::size_t walls = 0;
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(0, 0)));
  expect_entry(cache.find_pair(pairs, pair_key(0, 1)), pair_key(0, 1), action_with(1.0), false);
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(0, 2)));
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(0, 5)));
  expect_entry(cache.find_pair(pairs, pair_key(0, 7)), pair_key(0, 7), ContactAction{}, true);
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(1, 2)));
  expect_entry(cache.find_pair(pairs, pair_key(2, 3)), pair_key(2, 3), action_with(-0.5), true);
  expect_entry(cache.find_pair(pairs, pair_key(7, 9)), pair_key(7, 9), action_with(2.0), false);
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(7, 10)));
  EXPECT_FALSE(cache.find_pair(pairs, pair_key(9, 11)));

  // walls have their own cursor: unaffected by the pair lookups above
  expect_entry(cache.find_wall(walls, wall_key(WallKind::Bottom, 1)), wall_key(WallKind::Bottom, 1),
               action_with(3.0), false);
  EXPECT_FALSE(cache.find_wall(walls, wall_key(WallKind::Bottom, 4)));
  EXPECT_FALSE(cache.find_wall(walls, wall_key(WallKind::Bottom, 9)));
  expect_entry(cache.find_wall(walls, wall_key(WallKind::Piston, 0)), wall_key(WallKind::Piston, 0),
               action_with(4.0), true);
  EXPECT_FALSE(cache.find_wall(walls, wall_key(WallKind::Piston, 3)));
  expect_entry(cache.find_wall(walls, wall_key(WallKind::Piston, 4)), wall_key(WallKind::Piston, 4),
               action_with(5.0), false);

  // skipping keys with fresh cursors: a sparse ascending walk finds the later entries too
  pairs = 0;
  walls = 0;
  expect_entry(cache.find_pair(pairs, pair_key(7, 9)), pair_key(7, 9), action_with(2.0), false);
  EXPECT_FALSE(cache.find_wall(walls, wall_key(WallKind::Piston, 1)));
  expect_entry(cache.find_wall(walls, wall_key(WallKind::Piston, 4)), wall_key(WallKind::Piston, 4),
               action_with(5.0), false);

  // a cursor started at a key (a second piece's first lookup) finds what one from 0 finds
  std::size_t from = cache.pair_cursor_at(pair_key(1, 2));
  EXPECT_FALSE(cache.find_pair(from, pair_key(1, 2)));
  expect_entry(cache.find_pair(from, pair_key(2, 3)), pair_key(2, 3), action_with(-0.5), true);
  from = cache.pair_cursor_at(pair_key(2, 3));
  expect_entry(cache.find_pair(from, pair_key(2, 3)), pair_key(2, 3), action_with(-0.5), true);
  from = cache.pair_cursor_at(pair_key(9, 11));
  EXPECT_FALSE(cache.find_pair(from, pair_key(9, 11)));

  // what a state file saves: the entries that carry over, and a cache restored from them
  // answers every lookup as the stored one does
  ActionCache restored;
  restored.restore(carried_pairs(cache.last()), carried_walls(cache.last()));
  EXPECT_EQ(carried_pairs(restored.last()).size(), 4U);
  EXPECT_EQ(carried_walls(restored.last()).size(), 3U);
  std::size_t again = 0;
  EXPECT_FALSE(restored.find_pair(again, pair_key(0, 5)));
  expect_entry(restored.find_pair(again, pair_key(0, 7)), pair_key(0, 7), ContactAction{}, true);
  expect_entry(restored.find_pair(again, pair_key(7, 9)), pair_key(7, 9), action_with(2.0), false);
}

TEST(ActionCache, KeysOrderPairsByFirstThenSecondSphereAndWallsByKindThenSphere) {
  EXPECT_LT(pair_key(0, 4'000'000'000U), pair_key(1, 2));
  EXPECT_LT(pair_key(3, 4), pair_key(3, 5));
  EXPECT_LT(wall_key(WallKind::Bottom, 4'000'000'000U), wall_key(WallKind::Piston, 0));
}

/// A small cohesive packing on the bottom wall under a piston, which gives pairs and both
/// walls' contacts.
TinyScene small_heap() {
  TinyScene s(6.0, 5.0);  // 2 × 2 cells: neighbour offsets wrap
  s.world.walls.bottom.enabled = true;
  s.world.walls.piston.enabled = true;
  s.world.walls.piston.height = 5.65;  // 0.05 R above the top layer: a candidate at once
  s.world.walls.piston.force = 1.0;
  s.world.gravity = Vec3(0.0, 0.0, -1.0);
  s.settings.solver.tolerance = 1e-6;  // only the contact lists are checked
  // a staggered lattice, touching along x, through the periodic x boundary (6 = 3 × 2R)
  for (int layer = 0; layer < 3; ++layer) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 2; ++j) {
        const double shift = layer % 2 == 0 ? 0.0 : 0.7;
        s.add(Vec3(1.0 + 2.0 * i + shift, 1.2 + 2.5 * j + shift, 1.0 + 1.8 * layer));
      }
    }
  }
  return s;
}

template <typename Problem, typename Key>
void expect_strictly_ascending(const std::vector<Problem>& list, Key key, const char* what) {
  for (std::size_t k = 1; k < list.size(); ++k) {
    EXPECT_LT(key(list[k - 1]), key(list[k])) << what << " " << k;
  }
}

/// What a lookup finds of a stored contact: it was cohesive or carried a nonzero action.
bool is_kept(const ContactAction& action, std::uint8_t cohesive) {
  return cohesive != 0 || action.normal_force != 0.0 ||
         action.tangential_force.squaredNorm() != 0.0 ||
         action.rolling_torque.squaredNorm() != 0.0 || action.twisting_torque != 0.0;
}

/// Returns 1 if an entry was expected, so the caller can count the warm-started contacts.
int expect_same(LastAction found, const ContactAction* stored, int step) {
  if (stored == nullptr) {
    EXPECT_FALSE(found) << "step " << step;
    return 0;
  }
  EXPECT_TRUE(found) << "step " << step;
  if (!found) return 1;
  EXPECT_EQ(found.action->normal_force, stored->normal_force) << "step " << step;
  EXPECT_EQ(found.action->tangential_force, stored->tangential_force) << "step " << step;
  return 1;
}

TEST(ActionCache, ContactListsOfRealStepsAreSortedAsTheMergeRequires) {
  TinyScene s = small_heap();
  std::size_t pairs_seen = 0;
  std::size_t walls_seen = 0;
  std::size_t piston_seen = 0;
  int warm_pairs = 0;
  int warm_walls = 0;
  for (int step = 0; step < 20; ++step) {
    const Contacts previous = s.work.contacts;
    s.run(1);
    const Contacts& now = s.work.contacts;
    pairs_seen += now.pairs.size();
    walls_seen += now.walls.size();
    for (const WallProblem& w : now.walls) piston_seen += w.wall == WallKind::Piston ? 1 : 0;
    expect_strictly_ascending(
        now.pairs, [](const PairProblem& p) { return pair_key(p.a, p.b); }, "pair");
    expect_strictly_ascending(
        now.walls, [](const WallProblem& w) { return wall_key(w.wall, w.sphere); }, "wall");

    // the merge of this step's keys against the previous step's stored actions finds what a
    // linear search finds
    ActionCache cache;
    cache.store(previous);
    std::size_t pair_cursor = 0;
    std::size_t wall_cursor = 0;
    for (const PairProblem& p : now.pairs) {
      const ContactAction* stored = nullptr;
      for (std::size_t k = 0; k < previous.pairs.size(); ++k) {
        const PairProblem& q = previous.pairs[k];
        if (q.a == p.a && q.b == p.b &&
            is_kept(previous.pair_actions[k], previous.pair_cohesive[k])) {
          stored = &previous.pair_actions[k];
        }
      }
      warm_pairs += expect_same(cache.find_pair(pair_cursor, pair_key(p.a, p.b)), stored, step);
    }
    for (const WallProblem& w : now.walls) {
      const ContactAction* stored = nullptr;
      for (std::size_t k = 0; k < previous.walls.size(); ++k) {
        const WallProblem& v = previous.walls[k];
        if (v.wall == w.wall && v.sphere == w.sphere &&
            is_kept(previous.wall_actions[k], previous.wall_cohesive[k])) {
          stored = &previous.wall_actions[k];
        }
      }
      warm_walls +=
          expect_same(cache.find_wall(wall_cursor, wall_key(w.wall, w.sphere)), stored, step);
    }
  }
  EXPECT_GT(pairs_seen, 0U);
  EXPECT_GT(walls_seen, piston_seen);
  EXPECT_GT(piston_seen, 0U);
  EXPECT_GT(warm_pairs, 0);
  EXPECT_GT(warm_walls, 0);
}

TEST(ActionCacheDeathTest, UnsortedContactsAbortInDebugBuilds) {
#ifdef NDEBUG
  GTEST_SKIP() << "CDP_ASSERT is compiled out of release builds";
#else
  Contacts c;
  add_pair(c, 2, 3, action_with(1.0), false);
  add_pair(c, 0, 1, action_with(1.0), false);
  ActionCache cache;
  EXPECT_DEATH(cache.store(c), "pairs not strictly ascending");
#endif
}

TEST(ActionCacheDeathTest, ALookupBelowThePassedEntriesAbortsInDebugBuilds) {
#ifdef NDEBUG
  GTEST_SKIP() << "CDP_ASSERT is compiled out of release builds";
#else
  Contacts c;
  add_pair(c, 0, 1, action_with(1.0), false);
  add_pair(c, 2, 3, action_with(1.0), false);
  ActionCache cache;
  cache.store(c);
  std::size_t cursor = 0;
  EXPECT_TRUE(cache.find_pair(cursor, pair_key(2, 3)));
  // (0, 1) is stored but the cursor has passed it: the merge would find nothing
  EXPECT_DEATH(cache.find_pair(cursor, pair_key(0, 1)), "lookups not in ascending key order");
#endif
}

}  // namespace
}  // namespace cdpowder::testing
