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

struct CachedAction {
  std::uint64_t key = 0;
  ContactAction action;
  bool cohesive = false;  ///< the contact was cohesion-active in that step
};

class ActionCache {
 public:
  /// Replaces the cache with the actions of a solved step (pairs and walls, each sorted by key).
  void store(const Contacts& contacts);

  /// Merge-join lookups: from a cursor of the caller's (0 before a step's first lookup of
  /// the family), with keys in ascending order within each family; each call moves the
  /// cursor on. Returns nullptr if the contact did not exist in the previous step. The cache
  /// is only read, so pieces side by side look up with cursors of their own.
  const CachedAction* find_pair(std::size_t& cursor, std::uint64_t key) const {
    return find(pairs_, cursor, key);
  }

  const CachedAction* find_wall(std::size_t& cursor, std::uint64_t key) const {
    return find(walls_, cursor, key);
  }

  /// The cursor of a piece whose first lookup is `key`: the first entry not below it.
  [[nodiscard]] std::size_t pair_cursor_at(std::uint64_t key) const {
    return cursor_at(pairs_, key);
  }

  /// The stored entries, each family sorted by key (what a state file saves).
  [[nodiscard]] const std::vector<CachedAction>& pair_entries() const { return pairs_; }

  [[nodiscard]] const std::vector<CachedAction>& wall_entries() const { return walls_; }

  /// Replaces the cache with entries read back from a state file; each family must be
  /// sorted by key, as store() leaves it.
  void restore(std::vector<CachedAction> pairs, std::vector<CachedAction> walls);

 private:
  /// Inline: the build calls it once per contact per step (as a call of its own it took ≈ 5 %
  /// of the build's time; docs/performance.md, "The build's pairs in lanes").
  static const CachedAction* find(const std::vector<CachedAction>& entries, std::size_t& cursor,
                                  std::uint64_t key) {
    // a key below an entry the cursor has passed would miss that entry: lookups must ascend
    CDP_ASSERT(cursor == 0 || entries[cursor - 1].key < key, "lookups not in ascending key order");
    while (cursor < entries.size() && entries[cursor].key < key) ++cursor;
    if (cursor < entries.size() && entries[cursor].key == key) return &entries[cursor];
    return nullptr;
  }

  /// The first entry whose key is not below `key`.
  static std::size_t cursor_at(const std::vector<CachedAction>& entries, std::uint64_t key);

  std::vector<CachedAction> pairs_;
  std::vector<CachedAction> walls_;
};

}  // namespace cdpowder
