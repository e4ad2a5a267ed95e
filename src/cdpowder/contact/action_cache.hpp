// action_cache.hpp — last step's contact actions, keyed by the contact's bodies, for the
// warm start (physics.md §7.4) and the history cohesion rule (§6.2).
// Both the cache and each step's contact list are sorted by key, so the lookup is one
// merge pass: O(contacts), no hashing, no allocation once capacity is reached.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/assert.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

/// Key of a sphere pair a < b, or of a wall contact (wall kind in the top bits).
inline std::uint64_t pair_key(BodyIndex a, BodyIndex b) {
  return (static_cast<std::uint64_t>(a) << 32U) | b;
}

inline std::uint64_t wall_key(WallKind wall, BodyIndex sphere) {
  return (static_cast<std::uint64_t>(wall) << 32U) | sphere;
}

/// One stored contact as a state file saves it: its key, its action and its cohesion.
struct CachedAction {
  std::uint64_t key = 0;
  ContactAction action;
  bool cohesive = false;  ///< the contact was cohesion-active in that step
};

/// Whether a stored contact carries anything into the next step: it was cohesion-active, or
/// its action is nonzero. A zero-force, non-cohesive contact warm-starts as a new one would,
/// from a zero action and without a bond (the history rule, physics.md §6.2). (−0 counts as
/// zero, as it compares equal to it.)
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

class ActionCache {
 public:
  /// Replaces the cache with the actions of a solved step (pairs and walls, each sorted by
  /// key): every contact's key, action and cohesion, in three arrays per family. The test of
  /// what carries over is the lookup's, so the store is two block copies and one pass over the
  /// keys (docs/performance.md, "The warm-start store as block copies").
  void store(const Contacts& contacts);

  /// Merge-join lookups: from a cursor of the caller's (0 before a step's first lookup of
  /// the family), with keys in ascending order within each family; each call moves the
  /// cursor on. Empty if the contact did not exist in the previous step or carried nothing
  /// over. The cache is only read, so pieces side by side look up with cursors of their own.
  LastAction find_pair(std::size_t& cursor, std::uint64_t key) const {
    return find(pairs_, cursor, key);
  }

  LastAction find_wall(std::size_t& cursor, std::uint64_t key) const {
    return find(walls_, cursor, key);
  }

  /// The cursor of a piece whose first lookup is `key`: the first entry not below it.
  [[nodiscard]] std::size_t pair_cursor_at(std::uint64_t key) const {
    return cursor_at(pairs_.keys, key);
  }

  /// The entries that carry over (carries_over), each family sorted by key: what a state file
  /// saves, and all a lookup can find.
  [[nodiscard]] std::vector<CachedAction> pair_entries() const { return entries(pairs_); }

  [[nodiscard]] std::vector<CachedAction> wall_entries() const { return entries(walls_); }

  /// Replaces the cache with entries read back from a state file; each family must be
  /// sorted by key, as pair_entries() gives them.
  void restore(const std::vector<CachedAction>& pairs, const std::vector<CachedAction>& walls);

 private:
  /// One family (pairs or walls) of a step's contacts, index by index.
  struct Family {
    std::vector<std::uint64_t> keys;  ///< ascending
    std::vector<ContactAction> actions;
    std::vector<std::uint8_t> cohesive;  ///< 1 if cohesion-active

    void clear() {
      keys.clear();
      actions.clear();
      cohesive.clear();
    }
  };

  /// Inline: the build calls it once per contact per step (as a call of its own it took ≈ 5 %
  /// of the build's time; docs/performance.md, "The build's pairs in lanes").
  static LastAction find(const Family& family, std::size_t& cursor, std::uint64_t key) {
    const std::vector<std::uint64_t>& keys = family.keys;
    // a key below an entry the cursor has passed would miss that entry: lookups must ascend
    CDP_ASSERT(cursor == 0 || keys[cursor - 1] < key, "lookups not in ascending key order");
    while (cursor < keys.size() && keys[cursor] < key) ++cursor;
    if (cursor == keys.size() || keys[cursor] != key) return {};
    const ContactAction& action = family.actions[cursor];
    const bool cohesive = family.cohesive[cursor] != 0;
    if (!carries_over(action, cohesive)) return {};
    return {&action, cohesive};
  }

  /// The first entry whose key is not below `key`.
  static std::size_t cursor_at(const std::vector<std::uint64_t>& keys, std::uint64_t key);

  static std::vector<CachedAction> entries(const Family& family);
  static void fill(Family& family, const std::vector<CachedAction>& entries);

  Family pairs_;
  Family walls_;
};

}  // namespace cdpowder
