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
/// counted in result.repeated_steps once the step is committed.
///
/// A solve cut short by the stop request (SolverStats::stopped) abandons the whole step the
/// same way and returns nothing: the World, the warm-start cache and the stream are those
/// after the step before, the state a run never stopped also passes through, so a run
/// continued from it ends bit-identical. With a fixed Δt (`adaptive` false) there is one
/// solve.
std::optional<StepReport> step_unless_stopped(World& world, StepWorkspace& work,
                                              StepSettings& settings, bool adaptive,
                                              RunResult& result) {
  const TimeStepControl& control = settings.solver.time_step;
  const Rng sweep_order = work.solver.rng;
  StageTimes repeated_times{};
  std::int64_t repeated_steps = 0;
  std::int64_t repeated_sweeps = 0;
  StepReport report = begin_step(world, work, settings);
  solve_step(world, work, settings, report);
  while (!report.solver.stopped && adaptive &&
         report.diagnostics.max_cohesive_opening_per_range > control.max_opening_per_step &&
         settings.solver.dt > control.dt_min) {
    for (std::size_t s = 0; s < repeated_times.size(); ++s) repeated_times[s] += report.times[s];
    ++repeated_steps;
    repeated_sweeps += report.solver.sweeps;
    work.solver.rng = sweep_order;
    settings.solver.dt = retry_time_step(control, settings.solver.dt,
                                         report.diagnostics.max_cohesive_opening_per_range);
    report = begin_step(world, work, settings);
    solve_step(world, work, settings, report);
  }
  if (report.solver.stopped) {
    work.solver.rng = sweep_order;
    return std::nullopt;
  }
  for (std::size_t s = 0; s < repeated_times.size(); ++s) {
    result.stage_seconds[s] += repeated_times[s];
  }
  result.repeated_steps += repeated_steps;
  result.repeated_sweeps += repeated_sweeps;
  commit_step(world, work, settings, report);
  return report;
}

/// How the static solves after a step ended (run_simulation).
enum class StaticChecks {
  GoOn,     ///< none adopted: the run goes on
  Blocked,  ///< one was adopted: the run ends blocked
  Stopped,  ///< one was cut short by the stop request: asked again when the run continues
};

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
  const auto fraction_done = [&] {
    return adaptive ? std::min(1.0, elapsed() / budget)
                    : static_cast<double>(result.steps) / static_cast<double>(max_steps);
  };
  StepSettings current = settings;  // with the Δt of the step about to run
  // long solves (a static solve of 20 000 sweeps) ask the stop request after every sweep
  current.solver.stop_request = stop_requested ? &stop_requested : nullptr;
  std::optional<BlockedStateDetector>& detector = state.detector;
  if (run.until_blocked && !detector) detector.emplace(run.blocked, settings.solver.dt);
  int& deferred_windows = state.deferred_windows;
  bool& probing = state.probing;
  const double load = piston_load(world);
  // the grain volume is constant: computed once for the porosity check of every step
  const FaultLimits fault_limits{run.max_overlap, grain_volume(world.bodies)};
  const auto finish = [&] {
    result.wall_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

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

  // The static solves after a step, on copies. Their conditions are read from the state
  // (the detector's memory, the times of the last solves), and a solve counts only once it
  // has ended: a run stopped inside one asks the same question again first thing when it
  // is continued, as a run never stopped asked it after that step.
  const auto static_checks = [&]() {
    if (!detector) return StaticChecks::GoOn;
    const double fraction = fraction_done();
    const bool blocked = detector->blocked();
    // Blocked by the window's tests: the packing is measured on a static solve of a copy,
    // and adopted unless that solve shows a sphere out of balance; then the run goes on
    // unchanged and the test is repeated a window later, at most kMaxDeferredWindows times
    // (a packing whose static solve never balances is then measured as it is, and its
    // gauges say so; without the bound such a run could go on to max_duration).
    if (blocked && detector->window_complete(world.time - state.last_rest_check)) {
      World rest_world = world;
      StepWorkspace rest_work = work;
      const StepReport at_rest = solve_at_rest(rest_world, rest_work, current, run.blocked);
      if (at_rest.solver.stopped) return StaticChecks::Stopped;
      state.last_rest_check = world.time;
      if (spheres_balanced(at_rest, run.blocked, load) || deferred_windows >= kMaxDeferredWindows) {
        world = std::move(rest_world);
        work = std::move(rest_work);
        finish_at_rest(at_rest, fraction);
        return StaticChecks::Blocked;
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
    if (!blocked && probing && detector->at_rest_for_window() &&
        detector->window_complete(world.time - state.last_probe)) {
      const auto probe_start = std::chrono::steady_clock::now();
      World probe_world = world;
      StepWorkspace probe_work = work;
      const StepReport probe = solve_at_rest(probe_world, probe_work, current, run.blocked);
      if (probe.solver.stopped) return StaticChecks::Stopped;
      state.last_probe = world.time;
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
          return StaticChecks::Blocked;
        }
        ++result.unbalanced_rest_solves;
      }
    }
    return StaticChecks::GoOn;
  };

  // a run stopped inside a static solve of its last step: that solve first
  if (result.steps > 0) {
    const StaticChecks pending = static_checks();
    if (pending == StaticChecks::Stopped) result.interrupted = true;
    if (pending != StaticChecks::GoOn) return finish();
  }
  // result.steps counts the steps of every call, so k continues where a saved run stopped
  for (std::int64_t k = result.steps; k < max_steps && !budget_spent(); ++k) {
    current.solver.dt = state.dt;
    const std::optional<StepReport> report =
        step_unless_stopped(world, work, current, adaptive, result);
    if (!report) {  // stopped inside the solve: the state is the one after the step before
      result.interrupted = true;
      break;
    }
    account(*report);
    if (adaptive) state.dt = current.solver.dt;  // a repeated step continues from its shorter Δt
    if (detector) detector->update(world, result.last.diagnostics, current.solver.dt);
    if (observer) observer(world, result.last, fraction_done());
    // a state no physical run reaches ends the run here, before any test reads it
    result.fault = find_fault(world, work.contacts, result.last.diagnostics, fault_limits);
    if (result.fault) break;
    // the next Δt before the static solves: they leave the World as it is unless they end
    // the run, so it is the same either way, and a run stopped inside one has it already
    if (adaptive) {
      state.dt = next_time_step(settings.solver.time_step, current.solver.dt, world,
                                result.last.diagnostics.max_cohesive_opening_speed, settings.laws,
                                settings.solver.skin);
    }
    const StaticChecks checks = static_checks();
    if (checks == StaticChecks::Stopped) result.interrupted = true;
    if (checks != StaticChecks::GoOn) break;
    // not after the last step: a run whose steps are all done is complete, not interrupted
    const bool last_step = k + 1 >= max_steps || budget_spent();
    if (!last_step && stop_requested && stop_requested()) {
      result.interrupted = true;
      break;
    }
  }
  return finish();
}

}  // namespace cdpowder
