// sphere_loads.cpp — the contact loads on each sphere (sphere_loads.hpp).
#include "cdpowder/analysis/sphere_loads.hpp"

#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/contact/velocity_change.hpp"

namespace cdpowder {

SphereLoads sphere_contact_loads(const Contacts& contacts, std::size_t spheres) {
  // the passes' own update with Δt/m = Δt/I = 1: each record sums its contacts' force and
  // torque, fixed spheres included
  VelocityCache sums;
  sums.spheres.resize(spheres);
  for (SphereVelocity& s : sums.spheres) {
    s.dt_inverse_mass = 1.0;
    s.dt_inverse_inertia = 1.0;
  }
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    apply_pair_action(contacts.pairs[k], contacts.pair_actions[k], sums);
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    apply_wall_action(contacts.walls[k], contacts.wall_actions[k], sums);
  }
  SphereLoads loads;
  loads.force.reserve(spheres);
  loads.torque.reserve(spheres);
  for (const SphereVelocity& s : sums.spheres) {
    loads.force.push_back(s.linear);
    loads.torque.push_back(s.angular);
  }
  return loads;
}

}  // namespace cdpowder
