// energy_budget.cpp — bonds formed and broken by a merge over keys, the cohesion's potential
// energy, and the start and end measures of the budget (physics.md §17, "The energy budget").
#include "cdpowder/analysis/energy_budget.hpp"

#include "cdpowder/contact/action_cache.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace cdpowder {

namespace {

/// formed/broken of one family: the last step's keys and this step's records, both sorted by
/// key, with their cohesion flags.
template <typename Record>
void count_family(const std::vector<std::uint64_t>& last,
                  const std::vector<std::uint8_t>& last_bond, const std::vector<Record>& now,
                  const std::vector<std::uint8_t>& now_bond, std::int64_t& formed,
                  std::int64_t& broken) {
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < last.size() || j < now.size()) {
    const bool take_last =
        j == now.size() || (i < last.size() && contact_key(last[i]) <= contact_key(now[j]));
    const bool take_now =
        i == last.size() || (j < now.size() && contact_key(now[j]) <= contact_key(last[i]));
    const bool was = take_last && last_bond[i] != 0;
    const bool is = take_now && now_bond[j] != 0;
    formed += (is && !was) ? 1 : 0;
    broken += (was && !is) ? 1 : 0;
    if (take_last) ++i;
    if (take_now) ++j;
  }
}

}  // namespace

BondChanges bond_changes(const KeyedContacts& last, const Contacts& now) {
  BondChanges c;
  count_family(last.pair_keys, last.pair_cohesive, now.pairs, now.pair_cohesive, c.pairs_formed,
               c.pairs_broken);
  count_family(last.wall_keys, last.wall_cohesive, now.walls, now.wall_cohesive, c.walls_formed,
               c.walls_broken);
  return c;
}

double cohesive_energy(const Contacts& contacts, const ContactLaws& laws) {
  double u = 0.0;
  const auto add = [&u](double cohesion, double range, double gap) {
    u -= cohesion * std::max(0.0, range - std::max(gap, 0.0));
  };
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    if (contacts.pair_cohesive[k] != 0) {
      const PairProblem& p = contacts.pairs[k];
      add(p.cohesion, laws.spheres.cohesion_range, p.gap);
    }
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    if (contacts.wall_cohesive[k] != 0) {
      const WallProblem& w = contacts.walls[k];
      add(w.cohesion, laws.walls.cohesion_range, w.gap);
    }
  }
  return u;
}

double kinetic_energy(const World& world) {
  const Bodies& b = world.bodies;
  double k = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.fixed[i] != 0) continue;
    k += 0.5 * (b.mass(i) * b.velocity[i].squaredNorm() +
                b.inertia(i) * b.angular_velocity[i].squaredNorm());
  }
  const Piston& piston = world.walls.piston;
  if (piston.enabled) k += 0.5 * piston.mass * piston.velocity * piston.velocity;
  return k;
}

double height_moment(const World& world) {
  const Bodies& b = world.bodies;
  double moment = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.fixed[i] == 0) moment += b.mass(i) * b.position[i].z();
  }
  return moment;
}

bool budget_is_complete(const World& world) {
  const Bodies& b = world.bodies;
  const auto zero = [](const Vec3& v) { return v.squaredNorm() == 0.0; };
  return world.gravity.x() == 0.0 && world.gravity.y() == 0.0 &&
         std::all_of(b.external_force.begin(), b.external_force.end(), zero) &&
         std::all_of(b.external_torque.begin(), b.external_torque.end(), zero);
}

}  // namespace cdpowder
