// slab_solve.hpp — the passes and the mixing of a step cut into two slabs (slabs.hpp), in as
// few hand-overs between the threads as the order of the work allows. On this machine a
// hand-over (one run of SlabThreads) costs ≈ 2 µs, a tenth of a pass at paper size, so the
// work of one slab is one piece: its contacts and then the kinematic rule's pass over its
// spheres; the mixing is one run for the passes over the vectors and one for the changes it
// makes. Whatever touches both slabs (the contacts across the cut, the overflow pairs, the
// mixing's small fit) runs on the caller between the runs. The pieces are the same on one
// thread or two, and every sum over pieces is added in piece order: the same bits.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/solver/nlgs/anderson.hpp"
#include "cdpowder/solver/nlgs/coloured_pass.hpp"
#include "cdpowder/solver/nlgs/kinematic_change.hpp"
#include "cdpowder/solver/nlgs/mixed_actions.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"
#include "cdpowder/solver/nlgs/slab_threads.hpp"

namespace cdpowder {

/// One pass of a cut step (run_coloured_pass's order: the contacts across the cut, then each
/// slab's), each slab's contacts followed by the kinematic rule's pass over its spheres when
/// `kinematic` is given (with the RMS speed when `with_speed`), which sets `motion`.
PassSums cut_step_pass(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                       SlabThreads* threads, KinematicChange* kinematic, bool with_speed,
                       PassMotion& motion);

/// One mixing step of a cut step: `swept` ← the actions after the pass (flattened), the
/// accelerator's passes over the contacts of slab 0, of slab 1 and the rest (across the cut,
/// overflow, walls), its fit, and when that succeeds `mixed` ← the mixed actions, adopted by
/// the contacts with the velocity cache moved by the change: the rest first (on the caller),
/// then each slab's pairs and the kinematic rule's new snapshot of its spheres. Returns
/// whether the mixing was adopted (false: no history yet, or the fit failed; nothing changed).
bool mix_cut_step(const AlignedVector<double>& start, AlignedVector<double>& swept,
                  AlignedVector<double>& mixed, MixedModes modes, AndersonAccelerator& accelerator,
                  Contacts& contacts, VelocityCache& velocities, ColouredPass& pass,
                  SlabThreads* threads, KinematicChange* kinematic);

}  // namespace cdpowder
