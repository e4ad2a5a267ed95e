// scene_setup.hpp — turns a validated Scene into the World it describes: spheres from the
// particles CSV or a ballistic deposit, the cell, gravity, the bottom wall and the piston at
// its start height.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/model/world.hpp"

namespace cdpowder {

/// Builds the initial world. Throws ConfigError for bad particles or a cell too small for
/// them. An unset piston height puts the piston at rest on the highest sphere plus
/// piston.start_gap (physics.md §9). A deposit asks `stop_requested` as it goes and throws
/// Interrupted when it answers true.
World make_world(const Scene& scene, const StopRequest& stop_requested = {});

/// The world of `scene` around spheres the caller made (a program or the Python module; the
/// scene read with SceneReadOptions::spheres_from_caller): its cell, gravity, walls and
/// piston, placed as make_world places them. Throws ConfigError when the cell is too small
/// for the spheres (check_box_fits).
World make_world(const Scene& scene, Bodies spheres);

}  // namespace cdpowder
