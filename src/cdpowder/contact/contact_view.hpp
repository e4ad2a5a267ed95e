// contact_view.hpp — one contact of either kind, sphere pair or sphere–wall, as the loops that
// treat both alike see it (measurements, outputs), and the iteration over all of a step's
// contacts in Contacts' combined order: the pairs, then the walls. The solver's kernels keep
// their own loops over the two arrays: they differ in what they read.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/core/index.hpp"
#include "cdpowder/core/vec3.hpp"

#include <algorithm>
#include <cstddef>
#include <optional>

namespace cdpowder {

struct ContactView {
  std::size_t index = 0;         ///< Contacts' combined index: pairs first, then walls
  std::optional<WallKind> wall;  ///< the wall of a sphere–wall contact; empty for a pair
  BodyIndex a = 0;               ///< a pair's first sphere (a wall contact has none)
  BodyIndex b = 0;               ///< the pair's second sphere, or the wall contact's sphere
  Vec3 normal = Vec3::UnitZ();   ///< n, from a (or from the wall) to b, unit
  double gap = 0.0;              ///< g at the start of the step [R]
  /// length of the branch along n, centre to centre (R_a + R_b + g) or plane to centre
  /// (R + g) [R]
  double branch = 0.0;
  double cohesion = 0.0;  ///< F_c this step [F_coh]
  bool cohesive = false;  ///< cohesion-active this step
  const ContactAction* action = nullptr;

  [[nodiscard]] bool is_pair() const { return !wall.has_value(); }

  /// Carries force: S = R_n + F_c > 0 (local_problem.hpp).
  [[nodiscard]] bool closed() const { return is_closed(action->normal_force, cohesion); }
};

/// Calls visit(const ContactView&) for the contacts of combined indices [first, last), pairs
/// first, then walls. Contacts keeps its arrays of one kind equally long (checked in the
/// debug build).
template <typename Visit>
void for_each_contact_in(const Contacts& contacts, std::size_t first, std::size_t last,
                         Visit&& visit) {
  const std::size_t pairs = contacts.pairs.size();
  CDP_ASSERT(contacts.pair_actions.size() == pairs && contacts.pair_cohesive.size() == pairs &&
                 contacts.wall_actions.size() == contacts.walls.size() &&
                 contacts.wall_cohesive.size() == contacts.walls.size() && first <= last &&
                 last <= contacts.size(),
             "every pair and wall contact has its action and cohesion flag");
  for (std::size_t k = first; k < std::min(last, pairs); ++k) {
    const PairProblem& p = contacts.pairs[k];
    visit(ContactView{k, std::nullopt, p.a, p.b, p.normal, p.gap, p.lever_a + p.lever_b, p.cohesion,
                      contacts.pair_cohesive[k] != 0, &contacts.pair_actions[k]});
  }
  for (std::size_t k = std::max(first, pairs) - pairs; k + pairs < last; ++k) {
    const WallProblem& w = contacts.walls[k];
    visit(ContactView{pairs + k, w.wall, w.sphere, w.sphere, w.normal, w.gap, w.radius + w.gap,
                      w.cohesion, contacts.wall_cohesive[k] != 0, &contacts.wall_actions[k]});
  }
}

/// Calls visit(const ContactView&) for every contact, pairs first, then walls.
template <typename Visit>
void for_each_contact(const Contacts& contacts, Visit&& visit) {
  for_each_contact_in(contacts, 0, contacts.size(), visit);
}

}  // namespace cdpowder
