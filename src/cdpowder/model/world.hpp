// world.hpp — the physical state of a run: exactly what a checkpoint stores.
// Scratch buffers reused between steps live in StepWorkspace, not here.
#pragma once

#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"
#include "cdpowder/model/walls.hpp"

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

}  // namespace cdpowder
