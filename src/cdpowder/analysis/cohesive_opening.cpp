// cohesive_opening.cpp — one pass over the cohesion-active contacts.
#include "cdpowder/analysis/cohesive_opening.hpp"

#include "cdpowder/contact/contact_view.hpp"

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
  const Piston& piston = world.walls.piston;
  const double piston_speed = piston.enabled ? velocities.piston_velocity : piston.velocity;
  double pair_speed = kNone;
  double wall_speed = kNone;
  for_each_contact(contacts, [&](const ContactView& c) {
    if (!c.cohesive) return;
    if (c.is_pair()) {
      pair_speed = std::max(pair_speed, (end_velocity(c.b) - end_velocity(c.a)).dot(c.normal));
      return;
    }
    const double moving = *c.wall == WallKind::Piston ? piston_speed : 0.0;
    wall_speed = std::max(wall_speed, (end_velocity(c.b).z() - moving) * c.normal.z());
  });
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
