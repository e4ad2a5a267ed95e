// velocity_cache.hpp — v*, ω*: the end-of-step velocities being iterated (physics.md §5.3).
// The only per-body data the passes write. One cache line per sphere holds everything a
// contact visit needs of a body, so a visit touches two lines of body data.
#pragma once

#include "cdpowder/core/vec3.hpp"

#include <vector>

namespace cdpowder {

struct alignas(64) SphereVelocity {
  Vec3 linear = Vec3::Zero();       ///< v* [R/t0]
  Vec3 angular = Vec3::Zero();      ///< ω* [1/t0]
  double dt_inverse_mass = 0.0;     ///< Δt/m, 0 if fixed [t0/(ρR³)]
  double dt_inverse_inertia = 0.0;  ///< Δt/I, 0 if fixed [t0/(ρR⁵)]
};

static_assert(sizeof(SphereVelocity) == 64, "one cache line per sphere");

struct VelocityCache {
  std::vector<SphereVelocity> spheres;
  double piston_velocity = 0.0;  ///< V_P*, updated after every piston-contact visit (§7.1)
};

}  // namespace cdpowder
