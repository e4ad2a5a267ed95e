// action_cache.hpp — last step's contact actions, keyed by the contact's bodies, for the
// warm start (physics.md §7.4) and the history cohesion rule (§6.2).
// Both the cache and each step's contact list are sorted by key, so the lookup is one
// merge pass: O(contacts), no hashing, no allocation once capacity is reached. The cache
// holds the last step's keys (8 bytes a contact, copied) and its actions and cohesion flags
// (taken over by swap at the start of the next step); the geometry stays with the step's
// contacts, which the next detection refills (a copy of it cost 120 bytes a contact).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/core/pieces.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

static_assert(sizeof(BodyIndex) == 4, "a contact's two bodies in one 64-bit key");

/// Key of a sphere pair a < b, or of a wall contact (wall kind in the top bits).
inline std::uint64_t pair_key(BodyIndex a, BodyIndex b) {
  return (static_cast<std::uint64_t>(a) << 32U) | b;
}

inline std::uint64_t wall_key(WallKind wall, BodyIndex sphere) {
  return (static_cast<std::uint64_t>(wall) << 32U) | sphere;
}

/// The key of a contact record: its pair_key or wall_key.
inline std::uint64_t contact_key(const PairProblem& p) {
  return pair_key(p.a, p.b);
}

inline std::uint64_t contact_key(const WallProblem& w) {
  return wall_key(w.wall, w.sphere);
}

/// A key stands for itself (KeyedContacts holds the keys alone).
inline std::uint64_t contact_key(std::uint64_t key) {
  return key;
}

/// A step's contacts as the warm start, the bond count and a state file read them: each
/// family's keys (ascending), actions and cohesion flags, without their geometry.
struct KeyedContacts {
  std::vector<std::uint64_t> pair_keys;
  std::vector<ContactAction> pair_actions;
  std::vector<std::uint8_t> pair_cohesive;
  std::vector<std::uint64_t> wall_keys;
  std::vector<ContactAction> wall_actions;
  std::vector<std::uint8_t> wall_cohesive;

  void clear() {
    pair_keys.clear();
    pair_actions.clear();
    pair_cohesive.clear();
    wall_keys.clear();
    wall_actions.clear();
    wall_cohesive.clear();
  }
};

/// One stored contact as a state file saves it: its key, its action and its cohesion.
struct CachedAction {
  std::uint64_t key = 0;
  ContactAction action;
  bool cohesive = false;  ///< the contact was cohesion-active in that step
};

/// Whether a stored contact carries anything into the next step: it was cohesion-active, or
/// its action is nonzero (a vector part whose squared norm underflows to 0 counts as zero). A
/// zero-force, non-cohesive contact warm-starts as a new one would, from a zero action and without
/// a bond (the history rule, physics.md §6.2). (−0 counts as zero, as it compares equal to it.)
[[nodiscard]] inline bool carries_over(const ContactAction& action, bool cohesive) {
  return cohesive || action.normal_force != 0.0 || action.tangential_force.squaredNorm() != 0.0 ||
         action.rolling_torque.squaredNorm() != 0.0 || action.twisting_torque != 0.0;
}

/// What a lookup found of a contact in the last step: its action and whether it was
/// cohesion-active; empty where the contact was not in the last step or carried nothing over
/// (carries_over).
struct LastAction {
  const ContactAction* action = nullptr;
  bool cohesive = false;

  explicit operator bool() const { return action != nullptr; }
};

/// The contacts of `contacts` that carry something over (carries_over), each family in its
/// (ascending) key order: what a state file saves of a step's actions.
[[nodiscard]] std::vector<CachedAction> carried_pairs(const Contacts& contacts);
[[nodiscard]] std::vector<CachedAction> carried_walls(const Contacts& contacts);
[[nodiscard]] std::vector<CachedAction> carried_pairs(const KeyedContacts& contacts);
[[nodiscard]] std::vector<CachedAction> carried_walls(const KeyedContacts& contacts);

/// Both families' carried actions (carried_pairs, carried_walls).
struct CarriedActions {
  std::vector<CachedAction> pairs;
  std::vector<CachedAction> walls;
};

class ActionCache {
 public:
  /// Makes a solved step's contacts the last step's: copies their keys and swaps their
  /// actions and cohesion flags with the cache's own arrays. `contacts` keeps its records and
  /// is left with the cache's former actions and flags, whose contents are unspecified: the
  /// next detection clears them. (Copying the actions instead cost ≈ 7 µs of a front step,
  /// waiting on memory; docs/lab/2026-11-28-warm-start-swap-and-whole-run-overhead.md.)
  /// With `pieces`, the keys are copied in chunks on the runner's threads.
  void take(Contacts& contacts, PieceRunner* pieces = nullptr);

  /// take() on a copy of `contacts`, for tools and tests that go on reading theirs (it
  /// allocates; a step takes its contacts in begin_step instead, solver/step.hpp).
  void store(const Contacts& contacts);

  /// Merge-join lookups: from a cursor of the caller's (0 before a step's first lookup of
  /// the family), with keys in ascending order within each family; each call moves the
  /// cursor on. Empty if the contact did not exist in the previous step or carried nothing
  /// over. The cache is only read, so pieces side by side look up with cursors of their own.
  LastAction find_pair(std::size_t& cursor, std::uint64_t key) const {
    return find(last_.pair_keys, last_.pair_actions, last_.pair_cohesive, cursor, key);
  }

  LastAction find_wall(std::size_t& cursor, std::uint64_t key) const {
    return find(last_.wall_keys, last_.wall_actions, last_.wall_cohesive, cursor, key);
  }

  /// The cursor of a piece whose first lookup is `key`: the first entry not below it.
  [[nodiscard]] std::size_t pair_cursor_at(std::uint64_t key) const;
  [[nodiscard]] std::size_t wall_cursor_at(std::uint64_t key) const;

  /// The last step's contacts as the cache holds them: keys, actions and cohesion flags.
  [[nodiscard]] const KeyedContacts& last() const { return last_; }

  /// Replaces the cache with entries read back from a state file; each family must be
  /// sorted by key, as carried_pairs and carried_walls give them.
  void restore(const std::vector<CachedAction>& pairs, const std::vector<CachedAction>& walls);

 private:
  /// Inline: the build calls it once per contact per step (as a call of its own it took ≈ 5 %
  /// of the build's time; docs/lab/2026-11-28-build-pairs-and-warm-start-store.md).
  static LastAction find(const std::vector<std::uint64_t>& keys,
                         const std::vector<ContactAction>& actions,
                         const std::vector<std::uint8_t>& cohesive, std::size_t& cursor,
                         std::uint64_t key) {
    // a key below an entry the cursor has passed would miss that entry: lookups must ascend
    CDP_ASSERT(cursor == 0 || keys[cursor - 1] < key, "lookups not in ascending key order");
    while (cursor < keys.size() && keys[cursor] < key) ++cursor;
    if (cursor == keys.size() || keys[cursor] != key) return {};
    const ContactAction& action = actions[cursor];
    const bool was_cohesive = cohesive[cursor] != 0;
    if (!carries_over(action, was_cohesive)) return {};
    return {&action, was_cohesive};
  }

  KeyedContacts last_;
};

}  // namespace cdpowder
