// coloured_threads.hpp — the coloured sweep on several threads (solver.threads > 1). Within a
// colour no two contacts share a sphere, so each thread solves a contiguous share of the
// colour's batches; a spin barrier separates the colours, and the sequential group (overflow
// pairs, wall and piston contacts) runs on the calling thread alone. The visits are kept per
// batch and added to the sweep sums afterwards in the visiting order, so a sweep gives the
// bits of run_coloured_sweep for any thread count.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/solver/coloured_sweep.hpp"
#include "cdpowder/solver/sweep_sums.hpp"
#include "cdpowder/solver/sweep_threads.hpp"
#include "cdpowder/solver/velocity_cache.hpp"

#include <vector>

namespace cdpowder {

/// A visit of the sequential group, kept for the sums (closed_normal as in sweep_sums.hpp).
struct KeptVisit {
  double change_sq = 0.0;
  double closed_normal = -1.0;
};

/// The kept visits of one sweep; reused from sweep to sweep.
struct ThreadedSweepScratch {
  std::vector<BatchVisits> batches;   ///< batch i's visits
  std::vector<KeptVisit> sequential;  ///< sweep.sequential[i]'s visit
};

/// One sweep over the groups in sweep.group_order on all of `threads`: the same bits (state
/// and sums) as run_coloured_sweep.
SweepSums run_coloured_sweep_threaded(Contacts& contacts, VelocityCache& velocities,
                                      const ColouredSweep& sweep, SweepThreads& threads,
                                      ThreadedSweepScratch& scratch);

}  // namespace cdpowder
