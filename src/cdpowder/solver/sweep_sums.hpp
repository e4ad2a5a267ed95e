// sweep_sums.hpp — what a sweep reports to the stopping rules, shared by the scalar sweep
// (nlgs.cpp) and the coloured one (coloured_sweep.cpp), and the scalar visit both use.
#pragma once

#include "cdpowder/contact/local_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cdpowder {

/// One sweep's largest change and sums.
struct SweepSums {
  double max_change_sq = 0.0;  ///< largest squared correction of a visit [F_coh²]
  double sum_change_sq = 0.0;
  double sum_closed_normal = 0.0;
  std::size_t closed = 0;
};

/// Adds one visit; the sums depend on the order of the visits.
inline void add_visit(SweepSums& sums, const VisitChange& change, double normal_force,
                      double cohesion) {
  sums.max_change_sq = std::max(sums.max_change_sq, change.change_sq);
  sums.sum_change_sq += change.change_sq;
  if (normal_force + cohesion > 0.0) {
    sums.sum_closed_normal += std::abs(normal_force);
    ++sums.closed;
  }
}

/// A visit kept for later: with more than one thread the visits of a sweep are added to
/// the sums after it, in the visiting order, so the sums do not depend on the thread count.
/// closed_normal is |R_n| of a closed contact (R_n + F_c > 0), −1 for an open one.
inline double closed_normal(double normal_force, double cohesion) {
  return normal_force + cohesion > 0.0 ? std::abs(normal_force) : -1.0;
}

/// add_visit of a kept visit: the same operations in the same order.
inline void add_kept_visit(SweepSums& sums, double change_sq, double closed_normal) {
  sums.max_change_sq = std::max(sums.max_change_sq, change_sq);
  sums.sum_change_sq += change_sq;
  if (closed_normal >= 0.0) {
    sums.sum_closed_normal += closed_normal;
    ++sums.closed;
  }
}

/// Solves contact k of the combined index range (pairs first, then walls) with the scalar
/// kernels; returns the change and sets the contact's new normal force and its cohesion.
inline VisitChange solve_contact(ContactIndex k, Contacts& contacts, VelocityCache& velocities,
                                 double& normal_force, double& cohesion) {
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  std::vector<SphereVelocity>& spheres = velocities.spheres;
  if (k < n_pairs) {
    const PairProblem& p = contacts.pairs[k];
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

/// One visit of contact k with the scalar kernels, added to the sums.
inline void visit_contact(ContactIndex k, Contacts& contacts, VelocityCache& velocities,
                          SweepSums& sums) {
  double normal_force = 0.0;
  double cohesion = 0.0;
  const VisitChange change = solve_contact(k, contacts, velocities, normal_force, cohesion);
  add_visit(sums, change, normal_force, cohesion);
}

}  // namespace cdpowder
