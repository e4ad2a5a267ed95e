// integrate.cpp — velocity commit and position update.
#include "cdpowder/solver/integrate.hpp"

namespace cdpowder {

void integrate(const VelocityCache& velocities, double dt, World& world) {
  Bodies& bodies = world.bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies.fixed[i] != 0) continue;
    bodies.velocity[i] = velocities.spheres[i].linear;
    bodies.angular_velocity[i] = velocities.spheres[i].angular;
    bodies.position[i] += dt * bodies.velocity[i];
    world.box.wrap(bodies.position[i]);
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
