// action_cache.cpp — taking over and merge-joining last step's contact actions.
#include "cdpowder/contact/action_cache.hpp"

#include "cdpowder/core/assert.hpp"

#include <algorithm>

namespace cdpowder {

namespace {

/// The first entry of `keys` (ascending) not below `key`.
std::size_t cursor_at(const std::vector<std::uint64_t>& keys, std::uint64_t key) {
  return static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
}

template <typename Record>
std::vector<CachedAction> carried(const std::vector<Record>& records,
                                  const std::vector<ContactAction>& actions,
                                  const std::vector<std::uint8_t>& cohesive) {
  CDP_ASSERT(actions.size() == records.size() && cohesive.size() == records.size(),
             "a contact without its action or cohesion flag");
  std::vector<CachedAction> out;
  for (std::size_t k = 0; k < records.size(); ++k) {
    const bool was_cohesive = cohesive[k] != 0;
    if (!carries_over(actions[k], was_cohesive)) continue;
    out.push_back({contact_key(records[k]), actions[k], was_cohesive});
  }
  return out;
}

/// Checks (debug builds) that a family's keys ascend strictly, as the merge join needs.
template <typename Record>
void check_ascending(const std::vector<Record>& records, const char* what) {
  for (std::size_t k = 1; k < records.size(); ++k) {
    CDP_ASSERT(contact_key(records[k - 1]) < contact_key(records[k]), what);
  }
  static_cast<void>(what);  // read by the assertion alone
}

/// Appends the saved `entries` to one family's arrays.
void fill(const std::vector<CachedAction>& entries, std::vector<std::uint64_t>& keys,
          std::vector<ContactAction>& actions, std::vector<std::uint8_t>& cohesive) {
  for (const CachedAction& entry : entries) {
    keys.push_back(entry.key);
    actions.push_back(entry.action);
    cohesive.push_back(entry.cohesive ? 1 : 0);
  }
}

/// keys ← the keys of `records`, in their order, in chunks on `pieces` (each key written once).
template <typename Record>
void keys_of(const std::vector<Record>& records, std::vector<std::uint64_t>& keys,
             PieceRunner* pieces) {
  keys.resize(records.size());
  run_chunks(pieces, records.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) keys[k] = contact_key(records[k]);
  });
}

}  // namespace

std::vector<CachedAction> carried_pairs(const Contacts& contacts) {
  return carried(contacts.pairs, contacts.pair_actions, contacts.pair_cohesive);
}

std::vector<CachedAction> carried_walls(const Contacts& contacts) {
  return carried(contacts.walls, contacts.wall_actions, contacts.wall_cohesive);
}

std::vector<CachedAction> carried_pairs(const KeyedContacts& contacts) {
  return carried(contacts.pair_keys, contacts.pair_actions, contacts.pair_cohesive);
}

std::vector<CachedAction> carried_walls(const KeyedContacts& contacts) {
  return carried(contacts.wall_keys, contacts.wall_actions, contacts.wall_cohesive);
}

void ActionCache::take(Contacts& contacts, PieceRunner* pieces) {
  check_ascending(contacts.pairs, "pairs not strictly ascending by key (a, b)");
  check_ascending(contacts.walls, "walls not strictly ascending by key (wall, sphere)");
  CDP_ASSERT(contacts.pair_actions.size() == contacts.pairs.size() &&
                 contacts.pair_cohesive.size() == contacts.pairs.size() &&
                 contacts.wall_actions.size() == contacts.walls.size() &&
                 contacts.wall_cohesive.size() == contacts.walls.size(),
             "a contact without its action or cohesion flag");
  keys_of(contacts.pairs, last_.pair_keys, pieces);
  last_.pair_actions.swap(contacts.pair_actions);
  last_.pair_cohesive.swap(contacts.pair_cohesive);
  keys_of(contacts.walls, last_.wall_keys, pieces);
  last_.wall_actions.swap(contacts.wall_actions);
  last_.wall_cohesive.swap(contacts.wall_cohesive);
}

void ActionCache::store(const Contacts& contacts) {
  Contacts copy = contacts;
  take(copy);
}

std::size_t ActionCache::pair_cursor_at(std::uint64_t key) const {
  return cursor_at(last_.pair_keys, key);
}

std::size_t ActionCache::wall_cursor_at(std::uint64_t key) const {
  return cursor_at(last_.wall_keys, key);
}

void ActionCache::restore(const std::vector<CachedAction>& pairs,
                          const std::vector<CachedAction>& walls) {
  last_.clear();
  fill(pairs, last_.pair_keys, last_.pair_actions, last_.pair_cohesive);
  fill(walls, last_.wall_keys, last_.wall_actions, last_.wall_cohesive);
}

}  // namespace cdpowder
