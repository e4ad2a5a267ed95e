// action_cache.hpp — last step's contact actions, keyed by the contact's bodies, for the
// warm start (physics.md §7.4) and the history cohesion rule (§6.2).
// Both the cache and each step's contact list are sorted by key, so the lookup is one
// merge pass: O(contacts), no hashing, no allocation once capacity is reached.
#pragma once

#include "cdpowder/contact/local_problem.hpp"

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

  /// Merge-join lookups: call with keys in ascending order within each family.
  /// Returns nullptr if the contact did not exist in the previous step.
  const CachedAction* find_pair(std::uint64_t key) { return find(pairs_, pair_cursor_, key); }

  const CachedAction* find_wall(std::uint64_t key) { return find(walls_, wall_cursor_, key); }

  /// Rewinds the merge cursors before a new step's lookups.
  void rewind() { pair_cursor_ = wall_cursor_ = 0; }

  /// Lookups with a cursor of the caller's, for contacts looked up in pieces side by side:
  /// a piece starts its cursor at the first entry of its first key (pair_cursor_at) and calls
  /// with ascending keys. The cache is only read.
  [[nodiscard]] std::size_t pair_cursor_at(std::uint64_t key) const {
    return cursor_at(pairs_, key);
  }

  const CachedAction* find_pair(std::size_t& cursor, std::uint64_t key) const {
    return find(pairs_, cursor, key);
  }

  const CachedAction* find_wall(std::size_t& cursor, std::uint64_t key) const {
    return find(walls_, cursor, key);
  }

  /// The stored entries, each family sorted by key (what a state file saves).
  [[nodiscard]] const std::vector<CachedAction>& pair_entries() const { return pairs_; }

  [[nodiscard]] const std::vector<CachedAction>& wall_entries() const { return walls_; }

  /// Replaces the cache with entries read back from a state file; each family must be
  /// sorted by key, as store() leaves it.
  void restore(std::vector<CachedAction> pairs, std::vector<CachedAction> walls);

 private:
  static const CachedAction* find(const std::vector<CachedAction>& entries, std::size_t& cursor,
                                  std::uint64_t key);
  /// The first entry whose key is not below `key`.
  static std::size_t cursor_at(const std::vector<CachedAction>& entries, std::uint64_t key);

  std::vector<CachedAction> pairs_;
  std::vector<CachedAction> walls_;
  std::size_t pair_cursor_ = 0;
  std::size_t wall_cursor_ = 0;
};

}  // namespace cdpowder
