// build.hpp — stage 2 of a step: the inverse-mass terms and thresholds of every
// contact (physics.md §5.2), cohesion activity (§6.2), the warm start (§7.4) and the
// predicted velocities v* = v + Δt (F_ext/m + g) + Δt W·(warm-start actions) (§5.3, §7.6).
#pragma once

#include "cdpowder/analysis/energy_budget.hpp"
#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/solver/settings.hpp"

namespace cdpowder {

/// Completes the records that detect_contacts started and fills the velocity cache.
/// Reads last step's actions from `cache` (merge join; contacts must be sorted by key): on a
/// workspace that has run steps, after take_last_step (solver/step.hpp), as begin_step does.
/// With `pieces`, in two halves side by side on the runner's threads: the predicted
/// velocities and the contacts' records a half each, then the warm start's velocity changes,
/// each half those of its own spheres in contact order. The same bits as on one thread.
/// Returns the cohesive bonds the step formed and broke against the cache (the energy budget,
/// analysis/energy_budget.hpp), counted where the lookup finds each contact's last step.
BondChanges build_local_problems(const World& world, const StepSettings& settings,
                                 const ActionCache& cache, Contacts& contacts,
                                 VelocityCache& velocities, PieceRunner* pieces = nullptr);

}  // namespace cdpowder
