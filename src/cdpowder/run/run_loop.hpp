// run_loop.hpp — steps a world for a duration, or until the blocked state within a
// maximum duration, and reports every step to an observer (time series, progress).
// The loop prints nothing; the app decides what to show.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/run/blocked_state.hpp"
#include "cdpowder/run/run_fault.hpp"
#include "cdpowder/solver/step.hpp"

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>

namespace cdpowder {

/// Where a run's energy budget starts (analysis/energy_budget.hpp, physics.md §17, "The energy
/// budget"): the state the run began from, measured before its first step.
struct EnergyAtStart {
  double piston_height = 0.0;    ///< Z_P [R]
  double kinetic_energy = 0.0;   ///< spheres and piston [F_coh R]
  double height_moment = 0.0;    ///< Σ m z of the free spheres (height_moment)
  double cohesive_energy = 0.0;  ///< U_coh of the first step's contacts [F_coh R]
};

struct RunResult {
  bool blocked = false;      ///< the blocked state was reached (until_blocked runs)
  bool interrupted = false;  ///< stopped early on request (stop_requested returned true)
  std::int64_t steps = 0;
  std::int64_t total_passes = 0;
  std::int64_t capped_steps = 0;  ///< steps whose NLGS hit max_passes
  double min_dt = 0.0;            ///< shortest and longest Δt of the run's steps [t0]
  double max_dt = 0.0;
  /// adaptive Δt: steps undone and solved again with a shorter Δt because a contact opened
  /// by more than max_opening_per_step × d_coh, and their passes (not in steps/total_passes)
  std::int64_t repeated_steps = 0;
  std::int64_t repeated_passes = 0;
  /// steps of this process whose solve ran on more than one thread (ThreadChoice): a measure
  /// of the machine, like wall_seconds, so not saved in a state file
  std::int64_t threaded_steps = 0;
  double max_overlap_seen = 0.0;  ///< largest overlap after any step [R]
  /// largest max_cohesive_opening_speed × Δt / d_coh of any step: above ≈ 0.1 the cohesion
  /// range is crossed in a few steps and Δt should be smaller (physics.md §6.4)
  double max_cohesive_opening_per_range = 0.0;
  /// cohesive bonds formed and broken over the run's steps after its first (whose cache may
  /// be empty); the budget's start (energy_start) holds the first step's bonds instead
  BondChanges bonds;
  EnergyAtStart energy_start;
  /// false for a run continued from a format-1 state file, which kept no budget
  bool energy_known = true;
  double wall_seconds = 0.0;
  StageTimes stage_seconds{};  ///< summed over all steps
  StepReport last;             ///< report of the final step
  /// The static final solve of a blocked run (velocities zeroed, one step at
  /// BlockedCriteria::final_tolerance); empty unless blocked. Not counted in steps,
  /// total_passes or capped_steps; its time is in wall_seconds and stage_seconds.
  std::optional<SolverStats> final_solve;
  /// Static probes of the force balance (run_loop.cpp): how many ran, their passes and wall
  /// time (not in the counts above or in stage_seconds), and whether the last one ended the
  /// run (blocked with a window mean of the imbalance above its threshold).
  int probes = 0;
  std::int64_t probe_passes = 0;
  double probe_seconds = 0.0;
  bool blocked_by_probe = false;
  /// Why a compaction that came to rest is not blocked: its static solves stayed out of
  /// balance (a sphere's net force, or σzz/p off 1 without gravity) in
  /// kMaxDeferredWindows + 1 blocked windows of the run, and it ended there. Empty
  /// otherwise. Not in a state file: such a run has ended.
  std::string not_blocked;
  /// Static solves (of a blocked window, or probes) not adopted because a sphere was out of
  /// balance in them (net force above force_balance × F); the run went on after each.
  int unbalanced_rest_solves = 0;
  /// A state no physical run reaches (non-finite values, an overlap beyond
  /// RunConfig::max_overlap, the piston through the wall, a porosity outside (0, 1)): the
  /// run stopped after that step, neither blocked nor interrupted. Not in a state file: a
  /// failed run is not continued.
  std::optional<RunFault> fault;
};

/// Called after every step with the world after the step, its report, and the fraction of
/// the run's time budget used (duration, or max_duration for until_blocked runs); once more
/// after a blocked run's static final solve, with the same fraction.
using StepObserver = std::function<void(const World&, const StepReport&, double fraction)>;

// StopRequest (core/stop_request.hpp) is asked after every step; true ends the run there,
// as a complete but interrupted run.

/// Everything the time loop carries from one step to the next besides the World and the
/// StepWorkspace: the counts and gauges so far, the blocked-state test's window and when the
/// next static solve may run. A state file stores it (run/state_file.hpp), so a run resumed
/// from one takes the same decisions, step for step, as a run never stopped.
struct RunState {
  RunResult result;  ///< steps done so far (result.steps), sums and gauges
  /// the blocked-state test and its window (until_blocked runs; made at the first step)
  std::optional<BlockedStateDetector> detector;
  /// times of the last static solve on a copy, of which at most one per window may run: a
  /// blocked window's check, and a probe (kept apart, so that a failed probe never delays
  /// the check of a window that is blocked by its own tests) [t0]
  double last_rest_check = -std::numeric_limits<double>::infinity();
  double last_probe = -std::numeric_limits<double>::infinity();
  int deferred_windows = 0;  ///< blocked windows deferred by a sphere out of balance
  bool probing = true;       ///< false once a probe failed to converge
  bool started = false;      ///< the first call has set start_time and dt
  double start_time = 0.0;   ///< world.time when the run began [t0]
  double dt = 0.0;           ///< Δt of the next step [t0] (time_step_control.hpp)
};

RunResult run_simulation(World& world, StepWorkspace& work, const StepSettings& settings,
                         const RunConfig& run, const StepObserver& observer,
                         const StopRequest& stop_requested = {});

/// The same loop continued from `state` (a fresh RunState starts a run) and leaving in it
/// what a later call needs to go on: a run interrupted at step k and continued from the
/// state saved then ends bit-identical to one never interrupted. Returns state.result,
/// with wall_seconds summed over all calls.
RunResult run_simulation(World& world, StepWorkspace& work, const StepSettings& settings,
                         const RunConfig& run, RunState& state, const StepObserver& observer,
                         const StopRequest& stop_requested = {});

}  // namespace cdpowder
