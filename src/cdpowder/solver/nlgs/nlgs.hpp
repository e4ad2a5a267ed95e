// nlgs.hpp — stage 3 of a step: nonlinear Gauss–Seidel over the step's contact set
// (physics.md §7.1–7.3, §17).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/solver/nlgs/anderson.hpp"
#include "cdpowder/solver/nlgs/coloured_pass.hpp"
#include "cdpowder/solver/nlgs/kinematic_change.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"
#include "cdpowder/solver/nlgs/tile_order.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "cdpowder/solver/settings.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace cdpowder {

/// What the passes of one step did.
struct SolverStats {
  int passes = 0;               ///< passes performed
  bool converged = false;       ///< the stopping rule was met (false: capped at max_passes)
  double residual = 0.0;        ///< largest force correction of the last pass / force scale
  double contraction = 0.0;     ///< ρ, measured ratio of residuals per pass
  double error_estimate = 0.0;  ///< residual/(1 − ρ): remaining relative force error
  double relative_change =
      0.0;  ///< √(Σ|ΔX|²/Σ|X|²) of the last pass ([S+12] criterion II, RMS form)
  /// the kinematic rule's estimate of the largest error of a sphere's surface velocity over
  /// the RMS surface speed; 0 unless the rule is on (SolverSettings::kinematic_tolerance) and
  /// the step ran past the rule's window of passes [-]
  double kinematic_error = 0.0;
  double piston_speed_error = 0.0;  ///< the same for the piston, over its speed [-]
  double force_scale = 0.0;         ///< F_ref = max(F_coh, mean |R_n| of closed contacts) [F_coh]
  bool stopped = false;             ///< cut short by SolverSettings::stop_request (not converged)
  bool threaded = false;            ///< solved on more than one thread (ThreadChoice)
};

/// Scratch state of the solver reused across steps: the pass-order stream and the
/// buffers of the acceleration (no allocation in steady state).
struct NlgsWorkspace {
  explicit NlgsWorkspace(std::uint64_t seed) : rng(make_rng(seed, RngStream::PassOrder)) {}

  Rng rng;
  AndersonAccelerator accelerator;
  /// actions the pass started from, flattened (4–8 per contact); a mixing writes its
  /// accelerated actions over them
  AlignedVector<double> start;
  /// the pass started from the accelerator's last output instead (the last mixing was not
  /// adopted): the actions after a pass live in the accelerator alone (anderson.hpp)
  bool start_is_last_output = false;
  std::vector<ContactIndex> blocks;  ///< block permutation of the per-step order
  KinematicChange kinematic;         ///< the kinematic rule's velocity snapshot
  ColouredPass coloured;             ///< colours and batches of solver.kernel = "coloured"
  TileThreadsSlot threads;           ///< the workers of solver.threads ≥ 2
  ThreadChoice thread_choice;        ///< whether a tiled step runs on them (tile_threads.hpp)
  StepTiles tiles;                   ///< the step's tiling (tiles.hpp)
  std::vector<AndersonAccelerator::PassSums> range_sums;  ///< of a tiled step (tile_solve.hpp)
  TileOrder order;  ///< the records in tile order (tile_order.hpp)
  TileRanks ranks;  ///< which tiles this rank of an MPI job solves (tile_ranks.hpp)
};

/// Passes until the stopping rule holds or max_passes is reached. Each visit solves one
/// contact exactly with the others held fixed and pushes its change into the velocity
/// cache at once, so later visits in the same pass see it (§7.1). With
/// acceleration_depth > 0, every pass is followed by an Anderson mixing step.
/// `reference_force` is the force scale below which forces count as small (F_coh).
/// With the coloured kernel and `tiles` tiling the step (tiles.hpp), a pass visits the four
/// phases' tiles and the hub in an order drawn per step, and the kinematic rule and the mixing
/// run in pieces (kinematic_change.hpp, tile_solve.hpp): on threads (solver.threads ≥ 2) a phase's
/// tiles and the pieces run side by side, with the same bits as on one; ThreadChoice
/// (tile_threads.hpp) decides, block by block, whether a tiled step uses the threads.
SolverStats solve_nlgs(Contacts& contacts, VelocityCache& velocities,
                       const SolverSettings& settings, double reference_force, NlgsWorkspace& work,
                       const StepTiles* tiles = nullptr);

/// Fills contacts.visit_order for a new step: storage order, or a random permutation of
/// blocks (RandomEachStep; RandomEachPass reshuffles every pass inside solve_nlgs).
void prepare_visit_order(Contacts& contacts, VisitOrder policy, NlgsWorkspace& work);

/// One pass in the given order; returns the pass's largest change and sums. Exposed for
/// the benchmark of the kernel.
PassSums run_scalar_pass(Contacts& contacts, VelocityCache& velocities);

}  // namespace cdpowder
