// integrate.cpp — velocity commit and position update.
#include "cdpowder/solver/integrate.hpp"

#include <cstddef>
#include <cstdint>

namespace cdpowder {

void integrate(const VelocityCache& velocities, double dt, World& world) {
  Bodies& bodies = world.bodies;
  // through pointers and a box held in locals: the stores below could alias the vectors'
  // own pointers and the box, which would then be reloaded for every sphere
  const std::size_t n = bodies.size();
  const std::uint8_t* const fixed = bodies.fixed.data();
  const SphereVelocity* const next = velocities.spheres.data();
  Vec3* const velocity = bodies.velocity.data();
  Vec3* const angular_velocity = bodies.angular_velocity.data();
  Vec3* const position = bodies.position.data();
  const PeriodicBox box = world.box;
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed[i] != 0) continue;
    velocity[i] = next[i].linear;
    angular_velocity[i] = next[i].angular;
    position[i] += dt * velocity[i];
    box.wrap(position[i]);
  }
  Piston& piston = world.walls.piston;
  if (piston.enabled) {
    piston.velocity = velocities.piston_velocity;
    piston.height += dt * piston.velocity;
  }
  world.time += dt;
  ++world.step;
}

}  // namespace cdpowder
