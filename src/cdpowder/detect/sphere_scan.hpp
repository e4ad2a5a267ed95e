// sphere_scan.hpp — detection's passes over the spheres: the largest surface speed, which
// sets the step's candidate gap, and the candidate list's displacement test. Both run in
// lanes (sphere_scan_lanes.inc) with the scalar loops' results.
#pragma once

#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"

#include <cstddef>

namespace cdpowder {

/// The largest surface speed |v| + R |ω| of spheres [first, last), at least 0 (a NaN speed is
/// passed over) [R/t0].
double largest_surface_speed(const Bodies& bodies, std::size_t first, std::size_t last);

/// Whether each of spheres [first, last) is within √slack_sq of its anchor (the minimum image
/// of position[i] − anchor[i]; a NaN distance counts as within) [R²].
bool all_within(const Vec3* position, const Vec3* anchor, const PeriodicBox& box, double slack_sq,
                std::size_t first, std::size_t last);

}  // namespace cdpowder
