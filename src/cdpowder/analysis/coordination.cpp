// coordination.cpp — closed-contact counts.
#include "cdpowder/analysis/coordination.hpp"

#include <numeric>

namespace cdpowder {

std::vector<int> contacts_per_sphere(const Contacts& contacts, std::size_t sphere_count) {
  std::vector<int> count(sphere_count, 0);
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    if (is_closed(contacts.pair_actions[k].normal_force, p.cohesion)) {
      ++count[p.a];
      ++count[p.b];
    }
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    if (is_closed(contacts.wall_actions[k].normal_force, w.cohesion)) ++count[w.sphere];
  }
  return count;
}

double coordination_number(const Contacts& contacts, std::size_t sphere_count) {
  if (sphere_count == 0) return 0.0;
  const std::vector<int> count = contacts_per_sphere(contacts, sphere_count);
  return static_cast<double>(std::accumulate(count.begin(), count.end(), 0L)) /
         static_cast<double>(sphere_count);
}

}  // namespace cdpowder
