// cohesive_opening.cpp — one pass over the cohesion-active contacts.
#include "cdpowder/analysis/cohesive_opening.hpp"

#include <algorithm>

namespace cdpowder {

CohesiveOpening cohesive_opening(const World& world, const Contacts& contacts,
                                 const VelocityCache& velocities, const ContactLaws& laws,
                                 double dt) {
  const Bodies& bodies = world.bodies;
  // what integrate() leaves in bodies.velocity: v* unless the sphere is fixed
  const auto end_velocity = [&](BodyIndex i) -> const Vec3& {
    return bodies.fixed[i] != 0 ? bodies.velocity[i] : velocities.spheres[i].linear;
  };
  CohesiveOpening out;
  const auto track = [&](double opening_speed, double range) {
    out.speed = std::max(out.speed, opening_speed);
    if (range > 0.0) out.per_range = std::max(out.per_range, opening_speed * dt / range);
  };
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    if (contacts.pair_cohesive[k] == 0) continue;
    const PairProblem& p = contacts.pairs[k];
    track((end_velocity(p.b) - end_velocity(p.a)).dot(p.normal), laws.spheres.cohesion_range);
  }
  const Piston& piston = world.walls.piston;
  const double piston_speed = piston.enabled ? velocities.piston_velocity : piston.velocity;
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    if (contacts.wall_cohesive[k] == 0) continue;
    const WallProblem& w = contacts.walls[k];
    const double wall_speed = w.wall == WallKind::Piston ? piston_speed : 0.0;
    track((end_velocity(w.sphere).z() - wall_speed) * w.normal.z(), laws.walls.cohesion_range);
  }
  return out;
}

}  // namespace cdpowder
