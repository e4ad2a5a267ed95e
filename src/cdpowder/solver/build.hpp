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

#include <array>
#include <cstdint>
#include <vector>

namespace cdpowder {

/// What the build in pieces keeps from step to step, so that a step allocates only when its
/// contacts outgrow every earlier step's.
struct BuildScratch {
  /// Each piece's pairs whose sphere b a later piece owns, grouped by that piece, in pair
  /// order within a group: group d of piece p is crossing[p][group_starts[p][d] …
  /// group_starts[p][d + 1]).
  std::array<std::vector<std::uint32_t>, kMaxPieces> crossing;
  std::array<std::array<std::uint32_t, kMaxPieces + 1>, kMaxPieces> group_starts{};
  /// The same pairs in pair order, as the grouping finds them, and the piece that owns each
  /// one's b: the owner is looked up once a pair, and the placing reads only these.
  std::array<std::vector<std::uint32_t>, kMaxPieces> found;
  std::array<std::vector<std::uint8_t>, kMaxPieces> found_owner;
  /// The build's pieces: 0 fixes them by the pair count (one per kChunkIndices pairs, at
  /// least two); a test sets a count to cut a small packing into many.
  std::uint32_t pieces = 0;
};

/// Completes the records that detect_contacts started and fills the velocity cache.
/// Reads last step's actions from `cache` (merge join; contacts must be sorted by key): on a
/// workspace that has run steps, after take_last_step (solver/step.hpp), as begin_step does.
/// With `pieces`, in K pieces side by side on the runner's threads (K fixed by the pair count,
/// never by the threads), cut by sphere owner: each piece's share of the predicted velocities
/// and the walls' records, the records of the pairs whose sphere a it owns; then the warm
/// start's velocity changes, each piece those of its own spheres in contact order, one more
/// piece the piston's. The same bits as on one thread. `scratch` keeps the cut's lists from
/// step to step (a local one without it).
/// Returns the cohesive bonds the step formed and broke against the cache (the energy budget,
/// analysis/energy_budget.hpp), counted where the lookup finds each contact's last step.
BondChanges build_local_problems(const World& world, const StepSettings& settings,
                                 const ActionCache& cache, Contacts& contacts,
                                 VelocityCache& velocities, PieceRunner* pieces = nullptr,
                                 BuildScratch* scratch = nullptr);

}  // namespace cdpowder
