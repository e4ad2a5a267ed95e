// time_step_control.cpp — the two bounds of the next Δt, growth-limited and clamped.
#include "cdpowder/solver/time_step_control.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdpowder {

double next_time_step(const TimeStepControl& control, double dt, const World& world,
                      double max_cohesive_opening_speed, const ContactLaws& laws, double skin) {
  const Bodies& bodies = world.bodies;
  double surface_speed = std::abs(world.walls.piston.enabled ? world.walls.piston.velocity : 0.0);
  double smallest_radius = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    surface_speed =
        std::max(surface_speed,
                 bodies.velocity[i].norm() + bodies.radius[i] * bodies.angular_velocity[i].norm());
    smallest_radius = std::min(smallest_radius, bodies.radius[i]);
  }
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
  const double length = std::min(smallest_radius, skin > 0.0 ? skin : smallest_radius);
  if (surface_speed > 0.0 && std::isfinite(length)) {
    next = std::min(next, control.displacement_per_step * length / surface_speed);
  }
  return std::clamp(next, control.dt_min, control.dt_max);
}

double retry_time_step(const TimeStepControl& control, double dt, double opening_per_range) {
  const double scaled = dt * control.opening_per_step / opening_per_range;
  return std::max(control.dt_min, std::min(0.5 * dt, scaled));
}

}  // namespace cdpowder
