// tile_solve.hpp — the mixing of a tiled step (tiles.hpp) in pieces on the threads; the passes
// are run_coloured_pass's (coloured_pass.hpp). A phase's tiles touch no common sphere, so each
// is one piece, with its batched pairs, its overflow pairs and its walls; the hub's parts run on
// the caller. The pieces are the same on any number of threads, and every sum over pieces is
// added in piece order: the same bits.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/solver/nlgs/anderson.hpp"
#include "cdpowder/solver/nlgs/coloured_pass.hpp"
#include "cdpowder/solver/nlgs/kinematic_change.hpp"
#include "cdpowder/solver/nlgs/tile_ranks.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"

#include <vector>

namespace cdpowder {

struct MixedModes;  // mixed_actions.hpp (it brings the contact kernels, which only the solver's
                    // sources include)

/// One mixing step of a tiled step: the actions after the pass (flattened: the pairs in colour
/// order, the walls part by part in ColouredPass::mixing_walls, as `x` holds them) into the
/// accelerator's output(), its passes over each part against the iterate `x` the pass started
/// from (its batched pairs, overflow pairs and walls, their sums added in that order), its fit
/// with the parts' sums added in part order, and when that succeeds `mixed` ← the mixed actions
/// (`mixed` holds stride × contacts doubles and may be the vector `x` is in: x is not read after
/// the accelerator's passes), adopted by the contacts with the velocity cache moved by the
/// change: the hub's parts first (on the caller), then the tiles phase by phase, each part's
/// pairs and walls; the piston by the parts' changes in part order at the end; and the kinematic
/// rule's new snapshot piece by piece. `range_sums` is scratch (the accelerator's sums of each
/// part). With `ranks` active (tile_ranks.hpp) this rank passes over and mixes its own tiles and
/// the hub's parts as every rank does; the tiles' sums and piston changes go to every rank, and
/// the rows a phase's tiles moved go to the ranks that hold them: the bits of one process.
/// Returns whether the mixing was adopted (false: no history yet, or the fit failed; nothing
/// changed, and the next iterate is the accelerator's last_output()).
bool mix_tiled_step(const double* x, AlignedVector<double>& mixed, MixedModes modes,
                    AndersonAccelerator& accelerator, Contacts& contacts, VelocityCache& velocities,
                    ColouredPass& pass, TileThreads* threads, KinematicChange* kinematic,
                    std::vector<AndersonAccelerator::PassSums>& range_sums,
                    TileRanks* ranks = nullptr);

}  // namespace cdpowder
