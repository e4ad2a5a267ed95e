// finite.hpp — whether a world holds only finite numbers: the precondition of a step that
// CDP_ASSERT checks in debug builds (a NaN would otherwise spread silently through the
// passes and be reported steps later, far from its cause).
#pragma once

#include "cdpowder/model/world.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cdpowder {

inline bool all_finite(const std::vector<Vec3>& values) {
  return std::all_of(values.begin(), values.end(), [](const Vec3& v) { return v.allFinite(); });
}

inline bool all_finite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

/// Positions, velocities, radii, inverse masses, applied loads, the piston and gravity.
inline bool all_finite(const World& world) {
  const Bodies& b = world.bodies;
  const Piston& piston = world.walls.piston;
  return all_finite(b.position) && all_finite(b.velocity) && all_finite(b.angular_velocity) &&
         all_finite(b.radius) && all_finite(b.inverse_mass) && all_finite(b.inverse_inertia) &&
         all_finite(b.external_force) && all_finite(b.external_torque) &&
         std::isfinite(piston.height) && std::isfinite(piston.velocity) &&
         std::isfinite(piston.mass) && std::isfinite(piston.force) && world.gravity.allFinite();
}

}  // namespace cdpowder
