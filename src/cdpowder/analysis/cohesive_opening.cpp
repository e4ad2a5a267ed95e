// cohesive_opening.cpp — one pass over the cohesion-active contacts.
#include "cdpowder/analysis/cohesive_opening.hpp"

#include <algorithm>
#include <limits>

namespace cdpowder {

CohesiveOpening cohesive_opening(const World& world, const Contacts& contacts,
                                 const VelocityCache& velocities, const ContactLaws& laws,
                                 double dt) {
  const Bodies& bodies = world.bodies;
  // what integrate() leaves in bodies.velocity: v* unless the sphere is fixed
  const auto end_velocity = [&](BodyIndex i) -> const Vec3& {
    return bodies.fixed[i] != 0 ? bodies.velocity[i] : velocities.spheres[i].linear;
  };
  // the largest opening speed of each kind; s ↦ s Δt / d_coh rounds monotonically (Δt and
  // d_coh are positive), so its largest value is that of the largest speed: one division per
  // kind instead of one per contact, with the same bits
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  double pair_speed = kNone;
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    if (contacts.pair_cohesive[k] == 0) continue;
    const PairProblem& p = contacts.pairs[k];
    pair_speed = std::max(pair_speed, (end_velocity(p.b) - end_velocity(p.a)).dot(p.normal));
  }
  const Piston& piston = world.walls.piston;
  const double piston_speed = piston.enabled ? velocities.piston_velocity : piston.velocity;
  double wall_speed = kNone;
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    if (contacts.wall_cohesive[k] == 0) continue;
    const WallProblem& w = contacts.walls[k];
    const double moving = w.wall == WallKind::Piston ? piston_speed : 0.0;
    wall_speed = std::max(wall_speed, (end_velocity(w.sphere).z() - moving) * w.normal.z());
  }
  CohesiveOpening out;
  const auto track = [&](double opening_speed, double range) {
    out.speed = std::max(out.speed, opening_speed);
    if (range > 0.0) out.per_range = std::max(out.per_range, opening_speed * dt / range);
  };
  track(pair_speed, laws.spheres.cohesion_range);
  track(wall_speed, laws.walls.cohesion_range);
  return out;
}

}  // namespace cdpowder
