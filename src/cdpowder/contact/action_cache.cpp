// action_cache.cpp — storing and merge-joining last step's contact actions.
#include "cdpowder/contact/action_cache.hpp"

#include "cdpowder/core/assert.hpp"

#include <algorithm>

namespace cdpowder {

void ActionCache::store(const Contacts& contacts) {
  // the keys in one pass over the records; the actions and cohesion flags as block copies
  // (a vector's copy assignment keeps its capacity: no allocation once it is reached)
  pairs_.keys.resize(contacts.pairs.size());
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    pairs_.keys[k] = pair_key(p.a, p.b);
    CDP_ASSERT(k == 0 || pairs_.keys[k - 1] < pairs_.keys[k],
               "pairs not strictly ascending by key (a, b)");
  }
  pairs_.actions = contacts.pair_actions;
  pairs_.cohesive = contacts.pair_cohesive;
  walls_.keys.resize(contacts.walls.size());
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    walls_.keys[k] = wall_key(w.wall, w.sphere);
    CDP_ASSERT(k == 0 || walls_.keys[k - 1] < walls_.keys[k],
               "walls not strictly ascending by key (wall, sphere)");
  }
  walls_.actions = contacts.wall_actions;
  walls_.cohesive = contacts.wall_cohesive;
  CDP_ASSERT(pairs_.actions.size() == pairs_.keys.size() &&
                 pairs_.cohesive.size() == pairs_.keys.size() &&
                 walls_.actions.size() == walls_.keys.size() &&
                 walls_.cohesive.size() == walls_.keys.size(),
             "a contact without its action or cohesion flag");
}

void ActionCache::restore(const std::vector<CachedAction>& pairs,
                          const std::vector<CachedAction>& walls) {
  fill(pairs_, pairs);
  fill(walls_, walls);
}

void ActionCache::fill(Family& family, const std::vector<CachedAction>& entries) {
  family.clear();
  for (const CachedAction& entry : entries) {
    family.keys.push_back(entry.key);
    family.actions.push_back(entry.action);
    family.cohesive.push_back(entry.cohesive ? 1 : 0);
  }
}

std::vector<CachedAction> ActionCache::entries(const Family& family) {
  std::vector<CachedAction> out;
  for (std::size_t k = 0; k < family.keys.size(); ++k) {
    const bool cohesive = family.cohesive[k] != 0;
    if (!carries_over(family.actions[k], cohesive)) continue;
    out.push_back({family.keys[k], family.actions[k], cohesive});
  }
  return out;
}

std::size_t ActionCache::cursor_at(const std::vector<std::uint64_t>& keys, std::uint64_t key) {
  return static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
}

}  // namespace cdpowder
