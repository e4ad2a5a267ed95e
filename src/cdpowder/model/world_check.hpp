// world_check.hpp — whether a World holds a state a run can start or go on from: every
// value finite and in its range (physics.md §2). A state file read back, a world built from
// a caller's arrays and a world a Python callback may have written through its views are
// checked with it before a step runs on them: a radius of 0 or a negative inverse mass would
// otherwise step on and end as a result (a "blocked" packing) instead of a fault.
#pragma once

#include "cdpowder/model/world.hpp"

#include <optional>
#include <string>

namespace cdpowder {

/// The largest |coordinate| of a sphere's centre [R]. Doubles are spaced 1.2e-10 R there; at
/// 1e17 R they are 16 R apart and a contact's geometry is noise (a fault's overlap could not
/// even be measured twice alike), at 1e300 a position wraps into the cell as 0.
inline constexpr double kMaxCoordinate = 1e6;

/// The first value no run can hold, as one line naming it, the sphere and what is allowed:
/// arrays of the spheres of different lengths; a position, velocity, angular velocity,
/// external force or torque that is not finite; a centre farther than kMaxCoordinate; a radius not
/// finite and > 0; an inverse mass or inertia not finite and ≥ 0; a fixed flag other than 0 or 1,
/// or a fixed sphere with a mass; a cell side not finite and > 0; gravity or a piston value not
/// finite, a piston mass ≤ 0; a time not finite and ≥ 0; a negative step. Nothing when every value
/// is allowed.
std::optional<std::string> world_problem(const World& world);

}  // namespace cdpowder
