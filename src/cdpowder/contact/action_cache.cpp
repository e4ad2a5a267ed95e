// action_cache.cpp — storing and merge-joining last step's contact actions.
#include "cdpowder/contact/action_cache.hpp"

#include "cdpowder/core/assert.hpp"

#include <algorithm>
#include <utility>

namespace cdpowder {

namespace {

bool is_nonzero(const ContactAction& action) {
  return action.normal_force != 0.0 || action.tangential_force.squaredNorm() != 0.0 ||
         action.rolling_torque.squaredNorm() != 0.0 || action.twisting_torque != 0.0;
}

}  // namespace

void ActionCache::store(const Contacts& contacts) {
  pairs_.clear();
  walls_.clear();
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    CDP_ASSERT(
        k == 0 || pair_key(contacts.pairs[k - 1].a, contacts.pairs[k - 1].b) < pair_key(p.a, p.b),
        "pairs not strictly ascending by key (a, b)");
    const bool cohesive = contacts.pair_cohesive[k] != 0;
    // Zero-force, non-cohesive contacts carry nothing into the next step.
    if (!cohesive && !is_nonzero(contacts.pair_actions[k])) continue;
    pairs_.push_back({pair_key(p.a, p.b), contacts.pair_actions[k], cohesive});
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    CDP_ASSERT(k == 0 || wall_key(contacts.walls[k - 1].wall, contacts.walls[k - 1].sphere) <
                             wall_key(w.wall, w.sphere),
               "walls not strictly ascending by key (wall, sphere)");
    const bool cohesive = contacts.wall_cohesive[k] != 0;
    if (!cohesive && !is_nonzero(contacts.wall_actions[k])) continue;
    walls_.push_back({wall_key(w.wall, w.sphere), contacts.wall_actions[k], cohesive});
  }
}

void ActionCache::restore(std::vector<CachedAction> pairs, std::vector<CachedAction> walls) {
  pairs_ = std::move(pairs);
  walls_ = std::move(walls);
}

std::size_t ActionCache::cursor_at(const std::vector<CachedAction>& entries, std::uint64_t key) {
  return static_cast<std::size_t>(
      std::lower_bound(entries.begin(), entries.end(), key,
                       [](const CachedAction& entry, std::uint64_t k) { return entry.key < k; }) -
      entries.begin());
}

}  // namespace cdpowder
