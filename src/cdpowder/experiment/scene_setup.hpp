// scene_setup.hpp — turns a validated Scene into the World it describes: spheres from the
// particles CSV or a ballistic deposit, the cell, gravity, the bottom wall and the piston at
// its start height.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/model/world.hpp"

namespace cdpowder {

/// Builds the initial world. Throws ConfigError for bad particles or a cell too small for
/// them. An unset piston height puts the piston at rest on the highest sphere plus
/// piston.start_gap (physics.md §9).
World make_world(const Scene& scene);

}  // namespace cdpowder
