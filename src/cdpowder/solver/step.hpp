// step.hpp — one Moreau–Jean time step as five named stages (physics.md §7.6).
#pragma once

#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/detect/candidate_list.hpp"
#include "cdpowder/detect/cell_grid.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/nlgs/nlgs.hpp"
#include "cdpowder/solver/settings.hpp"

#include <array>

namespace cdpowder {

/// Stages of a step, in execution order; also the slots of StageTimes. Analyse also holds the
/// cohesive-opening gauge, which solve_step measures before stage 4 so that an adaptive Δt can
/// undo the step before the World changes (physics.md §6.4).
enum class Stage { DetectContacts, BuildLocalProblems, SolveNlgs, Integrate, Analyse, Count };

/// Wall-clock seconds spent per stage.
using StageTimes = std::array<double, static_cast<std::size_t>(Stage::Count)>;

struct StepReport {
  double dt = 0.0;  ///< Δt of the step [t0]
  SolverStats solver;
  StepDiagnostics diagnostics;
  StageTimes times{};
};

/// Everything reused from step to step that is not physical state: a checkpoint of a
/// World does not need it, except the action cache for a bit-identical warm start.
struct StepWorkspace {
  explicit StepWorkspace(std::uint64_t seed) : solver(seed) {}

  CellGrid grid;
  CandidateList candidates;  ///< sphere pairs reused across steps (detect/candidate_list.hpp)
  DetectionScratch detection;
  Contacts contacts;
  VelocityCache velocities;
  BuildScratch build;  ///< the build's lists in pieces (solver/build.hpp)
  ActionCache action_cache;
  /// `contacts` holds the last committed step, whose actions the next begin_step takes into
  /// action_cache (by swap, ActionCache::take); until then they are the state's actions
  /// (last_step_actions).
  bool last_step_in_contacts = false;
  NlgsWorkspace solver;
  /// The last step's solve ran on the threads (StepReport::solver.threaded): the next step's
  /// detection and build run on them too.
  bool threaded = false;
};

/// The actions of the last committed step that carry over (carried_pairs, carried_walls), which
/// warm-start the next step and are what a state file saves: of work.contacts from commit_step
/// until the next begin_step takes them, of the action cache after that (or after a state
/// file has been read back).
CarriedActions last_step_actions(const StepWorkspace& work);

/// begin_step's first act: the last committed step's contacts into the action cache (a swap
/// of arrays, ActionCache::take) if work.contacts still holds them. A tool or test that runs
/// detect_contacts and build_local_problems by hand on a workspace that has run steps calls
/// it first: detection would otherwise overwrite the last step's actions, and the build
/// warm-start from the step before them. With `pieces`, the keys are copied on its threads.
void take_last_step(StepWorkspace& work, PieceRunner* pieces = nullptr);

/// Advances `world` by one step of Δt = settings.solver.dt: begin_step, then finish_step.
StepReport step(World& world, StepWorkspace& work, const StepSettings& settings);

/// Stages 1–2 (detect, build), after taking the last committed step's contacts into the
/// action cache: leaves the step's contact problem in work.contacts (with the warm-start
/// actions) and work.velocities (v*, ω*, V_P* with those actions applied, §5.3).
/// For tools that read or solve the problem themselves; step() is the two halves in a row.
/// After a step whose solve ran on two threads, both stages run in halves on them too (the
/// same bits).
StepReport begin_step(World& world, StepWorkspace& work, const StepSettings& settings);

/// Stages 3–5 (solve, integrate, analyse) on the problem begin_step left in `work`; adds
/// their times and results to `report`: solve_step, then commit_step.
void finish_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report);

/// Stage 3 and the opening gauge: solves the problem begin_step left in `work` and sets
/// report.solver and the diagnostics' two cohesive-opening gauges (cohesive_opening.hpp).
/// Leaves the World and the action cache as begin_step left them, so a step abandoned here
/// is undone by restoring the pass-order stream (work.solver.rng) alone: that is how an
/// adaptive Δt solves a step again with a shorter Δt (run/run_loop.cpp). begin_step's
/// one change to the World, the periodic wrap of the positions, maps positions it has
/// wrapped onto themselves (PeriodicBox::wrap).
void solve_step(const World& world, StepWorkspace& work, const StepSettings& settings,
                StepReport& report);

/// Keeps a solved step: integrates (measuring the spheres on the way, the net force among
/// them: SphereMeasures), fills the rest of report.diagnostics, and leaves the step's contacts
/// in work.contacts as the last committed step's (last_step_in_contacts), for the outputs
/// and the next warm start.
void commit_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report);

/// Frees the scratch a step rebuilds (the candidate list, the solver's mixing history and
/// colour batches, the detection's pieces, the velocity cache) and, while `contacts` holds the
/// committed step, the action cache's older step, which the next begin_step replaces unread: a
/// run's last outputs need the committed contacts alone, and without the scratch their buffers
/// fit in the memory it held (a 16 240-sphere packing: about 20 % off the peak). Keeps the
/// contacts, the actions a state file saves (last_step_actions) and the random streams; a
/// workspace stepped on after it gives the same bits, only rebuilding first.
void release_step_scratch(StepWorkspace& work);

}  // namespace cdpowder
