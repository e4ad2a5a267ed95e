// action_cache.cpp — taking over and merge-joining last step's contact actions.
#include "cdpowder/contact/action_cache.hpp"

#include "cdpowder/core/assert.hpp"

#include <algorithm>

namespace cdpowder {

namespace {

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

/// Appends the saved `entries` to one family's arrays, each record made from its key by
/// `record_of` (the bodies alone: all a lookup reads).
template <typename Record, typename RecordOf>
void fill(const std::vector<CachedAction>& entries, std::vector<Record>& records,
          std::vector<ContactAction>& actions, std::vector<std::uint8_t>& cohesive,
          RecordOf record_of) {
  for (const CachedAction& entry : entries) {
    records.push_back(record_of(entry.key));
    actions.push_back(entry.action);
    cohesive.push_back(entry.cohesive ? 1 : 0);
  }
}

}  // namespace

std::vector<CachedAction> carried_pairs(const Contacts& contacts) {
  return carried(contacts.pairs, contacts.pair_actions, contacts.pair_cohesive);
}

std::vector<CachedAction> carried_walls(const Contacts& contacts) {
  return carried(contacts.walls, contacts.wall_actions, contacts.wall_cohesive);
}

void ActionCache::take(Contacts& contacts) {
  check_ascending(contacts.pairs, "pairs not strictly ascending by key (a, b)");
  check_ascending(contacts.walls, "walls not strictly ascending by key (wall, sphere)");
  CDP_ASSERT(contacts.pair_actions.size() == contacts.pairs.size() &&
                 contacts.pair_cohesive.size() == contacts.pairs.size() &&
                 contacts.wall_actions.size() == contacts.walls.size() &&
                 contacts.wall_cohesive.size() == contacts.walls.size(),
             "a contact without its action or cohesion flag");
  last_.pairs.swap(contacts.pairs);
  last_.pair_actions.swap(contacts.pair_actions);
  last_.pair_cohesive.swap(contacts.pair_cohesive);
  last_.walls.swap(contacts.walls);
  last_.wall_actions.swap(contacts.wall_actions);
  last_.wall_cohesive.swap(contacts.wall_cohesive);
}

void ActionCache::store(const Contacts& contacts) {
  Contacts copy = contacts;
  take(copy);
}

std::size_t ActionCache::pair_cursor_at(std::uint64_t key) const {
  const std::vector<PairProblem>& records = last_.pairs;
  return static_cast<std::size_t>(
      std::lower_bound(records.begin(), records.end(), key,
                       [](const PairProblem& p, std::uint64_t k) { return contact_key(p) < k; }) -
      records.begin());
}

void ActionCache::restore(const std::vector<CachedAction>& pairs,
                          const std::vector<CachedAction>& walls) {
  last_.clear();
  fill(pairs, last_.pairs, last_.pair_actions, last_.pair_cohesive, [](std::uint64_t key) {
    PairProblem p;
    p.a = static_cast<BodyIndex>(key >> 32U);
    p.b = static_cast<BodyIndex>(key & 0xffff'ffffU);
    return p;
  });
  fill(walls, last_.walls, last_.wall_actions, last_.wall_cohesive, [](std::uint64_t key) {
    WallProblem w;
    w.wall = static_cast<WallKind>(key >> 32U);
    w.sphere = static_cast<BodyIndex>(key & 0xffff'ffffU);
    return w;
  });
}

}  // namespace cdpowder
