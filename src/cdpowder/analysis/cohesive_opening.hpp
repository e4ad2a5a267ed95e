// cohesive_opening.hpp — the opening gauge of physics.md §6.4, measured on a solved step
// before it is integrated: an adaptive Δt (run/run_loop.cpp) decides from it whether
// to keep the step or solve it again with a shorter Δt, and a step not kept has then changed
// nothing of the World that needs undoing.
#pragma once

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/model/world.hpp"

namespace cdpowder {

struct CohesiveOpening {
  /// max over cohesion-active contacts of the normal opening speed V_n > 0 at the end of
  /// the step: a contact opens by V_n Δt per step, which must stay well below d_coh [R/t0]
  double speed = 0.0;
  /// max over cohesion-active contacts of V_n Δt / d_coh, each with its own d_coh (sphere
  /// pairs and walls may differ); §6.4 asks for ≤ 0.1 [-]
  double per_range = 0.0;
};

/// The opening of the step's cohesive contacts with the velocities integrate() will commit:
/// v*, ω*, V_P* of `velocities` for free spheres and an enabled piston, the World's own for
/// fixed spheres (integrate leaves those). Call after the solve and before integrate(); the
/// result is what the same measure gives on the World after integrate(), to the last bit.
/// With `pieces`, the contacts are measured in pieces_of(contacts) pieces side by side (a
/// maximum does not depend on the order, so the result is the same).
CohesiveOpening cohesive_opening(const World& world, const Contacts& contacts,
                                 const VelocityCache& velocities, const ContactLaws& laws,
                                 double dt, PieceRunner* pieces = nullptr);

}  // namespace cdpowder
