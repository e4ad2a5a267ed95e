// run_loop.cpp — the time loop with its stop conditions.
#include "cdpowder/experiment/run_loop.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/experiment/blocked_state.hpp"
#include "cdpowder/solver/time_step_control.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace cdpowder {

namespace {

/// How many blocked windows in a row a sphere out of balance may defer (run_simulation).
constexpr int kMaxDeferredWindows = 5;

/// The packing measured in static equilibrium: all velocities set to zero and one step
/// solved to the final tolerance. Its residual velocities are solver noise, and the piston
/// turns them into forces of M_P V_P/Δt (at V_P = 1e-5 R/t0 and Δt = 0.01 t0 on the
/// paper's piston, 1 F_coh, more than half the load F), so the stress is measured on the
/// forces of this step.
StepReport solve_at_rest(World& world, StepWorkspace& work, const StepSettings& settings,
                         const BlockedCriteria& criteria) {
  for (Vec3& v : world.bodies.velocity) v.setZero();
  for (Vec3& w : world.bodies.angular_velocity) w.setZero();
  world.walls.piston.velocity = 0.0;
  StepSettings final_settings = settings;
  final_settings.solver.tolerance = criteria.final_tolerance;
  final_settings.solver.max_sweeps = criteria.final_max_sweeps;
  // the stress is measured on this step's forces: the force residual alone decides
  final_settings.solver.kinematic_tolerance = 0.0;
  final_settings.solver.min_sweeps =
      std::min(settings.solver.min_sweeps, criteria.final_max_sweeps);
  return step(world, work, final_settings);
}

/// Whether every sphere of a static solve is in balance: its net force (and torque over its
/// radius, StepDiagnostics::max_net_force) below the blocked test's relative tolerance times
/// the piston's load (its push F plus its weight, piston_load). A sphere still pulled into a
/// contact, or still decelerating, passes the kinematic tests when the sphere-speed bound is loose
/// (an RMS over all spheres), but the static solve shows it: measured up to 0.37 F_coh in 4 of 380
/// runs of 100 spheres.
bool spheres_balanced(const StepReport& at_rest, const BlockedCriteria& criteria, double load) {
  return at_rest.diagnostics.max_net_force <= criteria.force_balance * load;
}

/// One step of an adaptive run: solved, and while it opened a cohesion-active contact by more
/// than max_opening_per_step × d_coh (and Δt is above dt_min), abandoned before it is
/// integrated and solved again with a shorter Δt (time_step_control.hpp). An abandoned step
/// has changed nothing but the sweep-order stream (solve_step, step.hpp), so undoing it
/// copies 16 bytes instead of the World and the action cache. Leaves the Δt used in
/// settings.solver.dt; the abandoned steps' time is added to result.stage_seconds and
/// counted in result.repeated_steps.
StepReport step_within_opening_bound(World& world, StepWorkspace& work, StepSettings& settings,
                                     RunResult& result) {
  const TimeStepControl& control = settings.solver.time_step;
  const Rng sweep_order = work.solver.rng;
  StepReport report = begin_step(world, work, settings);
  solve_step(world, work, settings, report);
  while (report.diagnostics.max_cohesive_opening_per_range > control.max_opening_per_step &&
         settings.solver.dt > control.dt_min) {
    for (std::size_t s = 0; s < result.stage_seconds.size(); ++s) {
      result.stage_seconds[s] += report.times[s];
    }
    ++result.repeated_steps;
    result.repeated_sweeps += report.solver.sweeps;
    work.solver.rng = sweep_order;
    settings.solver.dt = retry_time_step(control, settings.solver.dt,
                                         report.diagnostics.max_cohesive_opening_per_range);
    report = begin_step(world, work, settings);
    solve_step(world, work, settings, report);
  }
  commit_step(world, work, settings, report);
  return report;
}

}  // namespace

RunResult run_simulation(World& world, StepWorkspace& work, const StepSettings& settings,
                         const RunConfig& run, const StepObserver& observer,
                         const StopRequest& stop_requested) {
  RunState state;
  return run_simulation(world, work, settings, run, state, observer, stop_requested);
}

RunResult run_simulation(World& world, StepWorkspace& work, const StepSettings& settings,
                         const RunConfig& run, RunState& state, const StepObserver& observer,
                         const StopRequest& stop_requested) {
  RunResult& result = state.result;
  if (result.blocked) return result;  // a finished run has nothing left to do
  result.interrupted = false;         // a resumed run goes on
  const auto start = std::chrono::steady_clock::now();
  if (!state.started) {
    state.started = true;
    state.start_time = world.time;
    state.dt = settings.solver.dt;
  }
  const bool adaptive = settings.solver.time_step.adaptive;
  const double budget = run.until_blocked ? run.max_duration : run.duration;
  // a fixed Δt: the step count from the budget, so round-off in t never adds or drops a
  // step; an adaptive Δt: until the simulated time has reached the budget
  const std::int64_t max_steps =
      adaptive ? std::numeric_limits<std::int64_t>::max()
               : static_cast<std::int64_t>(std::llround(budget / settings.solver.dt));
  const auto elapsed = [&] { return world.time - state.start_time; };
  const auto budget_spent = [&] { return adaptive && elapsed() >= budget * (1.0 - 1e-12); };
  StepSettings current = settings;  // with the Δt of the step about to run
  std::optional<BlockedStateDetector>& detector = state.detector;
  if (run.until_blocked && !detector) detector.emplace(run.blocked, settings.solver.dt);
  int& deferred_windows = state.deferred_windows;
  bool& probing = state.probing;
  const double load = piston_load(world);
  // the grain volume is constant: computed once for the porosity check of every step
  const FaultLimits fault_limits{run.max_overlap, grain_volume(world.bodies)};

  const auto account = [&](const StepReport& report) {
    result.last = report;
    result.min_dt = result.steps == 0 ? report.dt : std::min(result.min_dt, report.dt);
    result.max_dt = std::max(result.max_dt, report.dt);
    ++result.steps;
    result.total_sweeps += report.solver.sweeps;
    if (!report.solver.converged) ++result.capped_steps;
    result.max_overlap_seen = std::max(result.max_overlap_seen, report.diagnostics.max_overlap);
    result.max_cohesive_opening_per_range = std::max(
        result.max_cohesive_opening_per_range, report.diagnostics.max_cohesive_opening_per_range);
    for (std::size_t s = 0; s < result.stage_seconds.size(); ++s) {
      result.stage_seconds[s] += report.times[s];
    }
  };
  // the static final solve is a measurement, not a step of the dynamics: reported as
  // accuracy.final_solve, outside the step and sweep counts (its time is in stage_seconds)
  const auto finish_at_rest = [&](const StepReport& at_rest, double fraction) {
    result.blocked = true;
    result.last = at_rest;
    for (std::size_t s = 0; s < result.stage_seconds.size(); ++s) {
      result.stage_seconds[s] += at_rest.times[s];
    }
    result.final_solve = at_rest.solver;
    if (observer) observer(world, result.last, fraction);
  };

  // result.steps counts the steps of every call, so k continues where a saved run stopped
  for (std::int64_t k = result.steps; k < max_steps && !budget_spent(); ++k) {
    current.solver.dt = state.dt;
    if (adaptive) {
      account(step_within_opening_bound(world, work, current, result));
      state.dt = current.solver.dt;  // a repeated step continues from its shorter Δt
    } else {
      account(step(world, work, current));
    }
    const double fraction = adaptive ? std::min(1.0, elapsed() / budget)
                                     : static_cast<double>(k + 1) / static_cast<double>(max_steps);
    const bool blocked =
        detector && detector->update(world, result.last.diagnostics, current.solver.dt);
    if (observer) observer(world, result.last, fraction);
    // a state no physical run reaches ends the run here, before any test reads it
    result.fault = find_fault(world, work.contacts, result.last.diagnostics, fault_limits);
    if (result.fault) break;
    // Blocked by the window's tests: the packing is measured on a static solve of a copy,
    // and adopted unless that solve shows a sphere out of balance; then the run goes on
    // unchanged and the test is repeated a window later, at most kMaxDeferredWindows times
    // (a packing whose static solve never balances is then measured as it is, and its
    // gauges say so; without the bound such a run could go on to max_duration).
    if (blocked && detector->window_complete(world.time - state.last_rest_check)) {
      state.last_rest_check = world.time;
      World rest_world = world;
      StepWorkspace rest_work = work;
      const StepReport at_rest = solve_at_rest(rest_world, rest_work, current, run.blocked);
      if (spheres_balanced(at_rest, run.blocked, load) || deferred_windows >= kMaxDeferredWindows) {
        world = std::move(rest_world);
        work = std::move(rest_work);
        finish_at_rest(at_rest, fraction);
        break;
      }
      ++deferred_windows;
      ++result.unbalanced_rest_solves;
    }
    // At rest for a whole window, but the window mean of the force imbalance is above its
    // threshold: that mean is of the dynamic steps' forces, and noise the solver leaves in
    // them can keep it there for good (measured: a 100-sphere packing at (μt, μn) = (1, 0)
    // whose freely spinning spheres kept the mean at ≈ 0.02 until max_duration, 5 000 t0).
    // So test the balance on a static solve of a copy instead, once per window: if the
    // packing at rest carries the load with every sphere in balance, it is blocked;
    // otherwise the run goes on unchanged.
    if (!blocked && probing && detector && detector->at_rest_for_window() &&
        detector->window_complete(world.time - state.last_probe)) {
      state.last_probe = world.time;
      const auto probe_start = std::chrono::steady_clock::now();
      World probe_world = world;
      StepWorkspace probe_work = work;
      const StepReport probe = solve_at_rest(probe_world, probe_work, current, run.blocked);
      ++result.probes;
      result.probe_sweeps += probe.solver.sweeps;
      result.probe_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - probe_start).count();
      // an unconverged static solve says nothing about the balance, and the next would
      // cost as much again: stop probing and leave the run to the window mean
      if (!probe.solver.converged) probing = false;
      if (probe.solver.converged &&
          probe.diagnostics.piston_imbalance < run.blocked.force_balance) {
        if (spheres_balanced(probe, run.blocked, load)) {
          world = std::move(probe_world);
          work = std::move(probe_work);
          result.blocked_by_probe = true;
          finish_at_rest(probe, fraction);
          break;
        }
        ++result.unbalanced_rest_solves;
      }
    }
    if (adaptive) {
      state.dt = next_time_step(settings.solver.time_step, current.solver.dt, world,
                                result.last.diagnostics.max_cohesive_opening_speed, settings.laws,
                                settings.solver.skin);
    }
    if (stop_requested && stop_requested()) {
      result.interrupted = true;
      break;
    }
  }
  result.wall_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace cdpowder
