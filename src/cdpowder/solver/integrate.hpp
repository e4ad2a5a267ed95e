// integrate.hpp — stage 4 of a step: commit the iterated velocities and advance the
// positions with them (implicit Euler in the velocities, physics.md §3), measuring the
// spheres on the way.
#pragma once

#include "cdpowder/analysis/sphere_measures.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/model/world.hpp"

namespace cdpowder {

/// v ← v*, ω ← ω*, V_P ← V_P*; r ← r + Δt v (wrapped into the box), Z_P ← Z_P + Δt V_P;
/// t ← t + Δt; and the spheres' measures on the way. Fixed spheres keep their velocities and
/// positions. Sphere orientations are not integrated: no law depends on them (§3). In pieces
/// of spheres fixed by their count (indices_per_piece), side by side on `pieces` when given;
/// each piece's sums in index order, added in piece order: the same bits on any number of
/// threads.
SphereMeasures integrate(const VelocityCache& velocities, double dt, World& world,
                         PieceRunner* pieces = nullptr);

}  // namespace cdpowder
