// time_step_control.cpp — the two bounds of the next Δt, growth-limited and clamped.
#include "cdpowder/solver/time_step_control.hpp"

#include "cdpowder/detect/sphere_scan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdpowder {

SurfaceMotion surface_motion(const World& world, double sphere_speed, double smallest_radius) {
  const Piston& piston = world.walls.piston;
  return {std::max(std::abs(piston.enabled ? piston.velocity : 0.0), sphere_speed),
          smallest_radius};
}

SurfaceMotion surface_motion(const World& world) {
  const Bodies& bodies = world.bodies;
  return surface_motion(world, largest_surface_speed(bodies, 0, bodies.size()),
                        bodies.min_radius());
}

double next_time_step(const TimeStepControl& control, double dt, const SurfaceMotion& motion,
                      double max_cohesive_opening_speed, const ContactLaws& laws, double skin) {
  double next = std::min(control.dt_max, control.growth * dt);
  // the smaller cohesion range of the two laws bounds the opening (walls may differ)
  double range = std::numeric_limits<double>::infinity();
  for (const ContactLaw* law : {&laws.spheres, &laws.walls}) {
    if (law->cohesion_force > 0.0 && law->cohesion_range > 0.0) {
      range = std::min(range, law->cohesion_range);
    }
  }
  if (max_cohesive_opening_speed > 0.0 && std::isfinite(range)) {
    next = std::min(next, control.opening_per_step * range / max_cohesive_opening_speed);
  }
  const double length =
      std::min(motion.smallest_radius, skin > 0.0 ? skin : motion.smallest_radius);
  if (motion.speed > 0.0 && std::isfinite(length)) {
    next = std::min(next, control.displacement_per_step * length / motion.speed);
  }
  return std::clamp(next, control.dt_min, control.dt_max);
}

double retry_time_step(const TimeStepControl& control, double dt, double opening_per_range) {
  const double scaled = dt * control.opening_per_step / opening_per_range;
  return std::max(control.dt_min, std::min(0.5 * dt, scaled));
}

}  // namespace cdpowder
