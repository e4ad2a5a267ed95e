// visit_contact.hpp — one visit of a contact with the scalar kernels (local_solve.hpp), added
// to a pass's sums: the scalar pass's every visit and the coloured pass's sequential ones
// (the piston's contacts, the overflow pairs). For the solver's sources only.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cdpowder {

/// Adds one visit; the sums depend on the order of the visits.
inline void add_visit(PassSums& sums, const VisitChange& change, double normal_force,
                      double cohesion) {
  sums.max_change_sq = std::max(sums.max_change_sq, change.change_sq);
  sums.sum_change_sq += change.change_sq;
  if (is_closed(normal_force, cohesion)) {
    sums.sum_closed_normal += std::abs(normal_force);
    ++sums.closed;
  }
}

/// Solves contact k of the combined index range (pairs first, then walls) with the scalar
/// kernels; returns the change and sets the contact's new normal force and its cohesion.
/// `record_of` (the coloured pass's storage index) names pair k's record where the actions are
/// in another order than the records (ColouredPass::pair_record); null: the same order.
inline VisitChange solve_contact(ContactIndex k, Contacts& contacts, VelocityCache& velocities,
                                 double& normal_force, double& cohesion,
                                 const ContactIndex* record_of = nullptr) {
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  std::vector<SphereVelocity>& spheres = velocities.spheres;
  if (k < n_pairs) {
    const PairProblem& p = pair_record_at(contacts, record_of, k);
    ContactAction& action = contacts.pair_actions[k];
    const VisitChange change = solve_pair(p, action, spheres[p.a], spheres[p.b]);
    normal_force = action.normal_force;
    cohesion = p.cohesion;
    return change;
  }
  const WallProblem& w = contacts.walls[k - n_pairs];
  ContactAction& action = contacts.wall_actions[k - n_pairs];
  const VisitChange change = solve_wall(w, action, spheres[w.sphere], velocities.piston_velocity);
  normal_force = action.normal_force;
  cohesion = w.cohesion;
  return change;
}

/// One visit of contact k with the scalar kernels, added to the sums (`record_of` as in
/// solve_contact).
inline void visit_contact(ContactIndex k, Contacts& contacts, VelocityCache& velocities,
                          PassSums& sums, const ContactIndex* record_of = nullptr) {
  double normal_force = 0.0;
  double cohesion = 0.0;
  const VisitChange change =
      solve_contact(k, contacts, velocities, normal_force, cohesion, record_of);
  add_visit(sums, change, normal_force, cohesion);
}

}  // namespace cdpowder
