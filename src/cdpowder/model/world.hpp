// world.hpp — the physical state of a run: exactly what a checkpoint stores.
// Scratch buffers reused between steps live in StepWorkspace, not here.
#pragma once

#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"
#include "cdpowder/model/walls.hpp"

#include <algorithm>
#include <cstdint>

namespace cdpowder {

struct World {
  Bodies bodies;
  Walls walls;
  PeriodicBox box;
  Vec3 gravity = Vec3::Zero();  ///< g, acceleration of every free sphere [R/t0²]; the paper: 0
  double time = 0.0;            ///< t [t0]
  std::int64_t step = 0;        ///< completed steps
};

/// The force the spheres must push the piston up with for it to rest: the applied push F
/// plus the piston's weight −M_P g_z [F_coh]. F alone without gravity (the paper's case).
/// The piston's force balance and the blocked state are judged against it.
inline double piston_load(const World& world) {
  const Piston& piston = world.walls.piston;
  return piston.force - piston.mass * world.gravity.z();
}

/// The weight of the free spheres, Σ m_i |g| [F_coh]: what the bottom wall carries when they
/// rest on it.
inline double sphere_weight(const World& world) {
  double mass = 0.0;  // a fixed sphere (mass() = 0) rests on nothing
  for (std::size_t i = 0; i < world.bodies.size(); ++i) mass += world.bodies.mass(i);
  return mass * world.gravity.norm();
}

/// The load a packing at rest carries, the force scale of the blocked test's balance
/// (physics.md §9): the piston's (piston_load); without a piston, the spheres' weight, and at
/// least `cohesion_force`, one bond's F_coh, so a packing under no load is held to the scale
/// of its cohesion [F_coh].
inline double resting_load(const World& world, double cohesion_force) {
  if (world.walls.piston.enabled) return piston_load(world);
  return std::max(sphere_weight(world), cohesion_force);
}

}  // namespace cdpowder
