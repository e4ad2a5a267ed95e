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

}  // namespace cdpowder
