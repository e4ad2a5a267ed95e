// integrate.hpp — stage 4 of a step: commit the iterated velocities and advance the
// positions with them (implicit Euler in the velocities, physics.md §3), measuring the
// spheres on the way.
#pragma once

#include "cdpowder/analysis/sphere_measures.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/model/world.hpp"

namespace cdpowder {

/// v ← v*, ω ← ω*, V_P ← V_P*; r ← r + Δt v (wrapped into the box), Z_P ← Z_P + Δt V_P;
/// t ← t + Δt; and the spheres' measures on the way. Fixed spheres keep their velocities and
/// positions. Sphere orientations are not integrated: no law depends on them (§3).
SphereMeasures integrate(const VelocityCache& velocities, double dt, World& world);

}  // namespace cdpowder
