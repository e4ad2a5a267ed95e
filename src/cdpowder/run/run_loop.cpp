// run_loop.cpp — the time loop with its stop conditions.
#include "cdpowder/run/run_loop.hpp"

#include "cdpowder/analysis/energy_budget.hpp"
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/run/blocked_state.hpp"
#include "cdpowder/solver/time_step_control.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace cdpowder {

namespace {

/// How many blocked windows a sphere out of balance may defer in a run (run_simulation).
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
  final_settings.solver.max_passes = criteria.final_max_passes;
  // the stress is measured on this step's forces: the force residual alone decides
  final_settings.solver.kinematic_tolerance = 0.0;
  final_settings.solver.min_passes =
      std::min(settings.solver.min_passes, criteria.final_max_passes);
  return step(world, work, final_settings);
}

/// Whether every sphere of a static solve is in balance: its net force (and torque over its
/// radius, StepDiagnostics::max_net_force) below the blocked test's relative tolerance times
/// the load the packing carries (resting_load: the piston's push F plus its weight, or
/// without a piston the spheres' weight, at least F_coh). A sphere still pulled into a
/// contact, or still decelerating, passes the kinematic tests when the sphere-speed bound is loose
/// (an RMS over all spheres), but the static solve shows it: measured up to 0.37 F_coh in 4 of 380
/// runs of 100 spheres.
bool spheres_balanced(const StepReport& at_rest, const BlockedCriteria& criteria, double load) {
  return at_rest.diagnostics.max_net_force <= criteria.force_balance * load;
}

/// How far σzz/p of a static solve may be from 1 in a blocked packing (physics.md §17, §11.2).
constexpr double kStressBalance = 0.01;

/// Why the static solve `rest` is not a blocked packing, or nothing: a sphere out of balance
/// (spheres_balanced), or, with a piston and without gravity, σzz/p off 1 by more than
/// kStressBalance (the stress of a packing at rest between the walls equals the push; heavy
/// spheres that barely move pass the window's tests at 0.62). Under gravity σzz also carries
/// part of the spheres' weight, and without a piston there is no push: the net force alone
/// decides.
std::optional<std::string> balance_problem(const World& world, const Contacts& contacts,
                                           const StepReport& at_rest,
                                           const BlockedCriteria& criteria, double load) {
  if (!spheres_balanced(at_rest, criteria, load)) {
    return fmt::format(
        "a sphere stays out of balance at rest (largest net force {:.3g} F_coh, "
        "above run.blocked.force_balance × load = {:.3g} F_coh)",
        at_rest.diagnostics.max_net_force, criteria.force_balance * load);
  }
  const double pressure = load / world.box.area();
  if (world.walls.piston.enabled && world.gravity.isZero() && pressure > 0.0) {
    const double ratio = stress_tensors(contacts, packing_volume(world)).total(2, 2) / pressure;
    if (!(std::abs(ratio - 1.0) <= kStressBalance)) {
      return fmt::format(
          "σzz/p = {:.4f} at rest, expected 1 within {} (the packing does not "
          "carry the push)",
          ratio, kStressBalance);
    }
  }
  return std::nullopt;
}

/// One step of an adaptive run: solved, and while it opened a cohesion-active contact by more
/// than max_opening_per_step × d_coh (and Δt is above dt_min), abandoned before it is
/// integrated and solved again with a shorter Δt (time_step_control.hpp). An abandoned step
/// has changed nothing but the pass-order stream (solve_step, step.hpp), so undoing it
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
  const Rng pass_order = work.solver.rng;
  StageTimes repeated_times{};
  std::int64_t repeated_steps = 0;
  std::int64_t repeated_passes = 0;
  StepReport report = begin_step(world, work, settings);
  solve_step(world, work, settings, report);
  while (!report.solver.stopped && adaptive &&
         report.diagnostics.max_cohesive_opening_per_range > control.max_opening_per_step &&
         settings.solver.dt > control.dt_min) {
    for (std::size_t s = 0; s < repeated_times.size(); ++s) repeated_times[s] += report.times[s];
    ++repeated_steps;
    repeated_passes += report.solver.passes;
    work.solver.rng = pass_order;
    settings.solver.dt = retry_time_step(control, settings.solver.dt,
                                         report.diagnostics.max_cohesive_opening_per_range);
    report = begin_step(world, work, settings);
    solve_step(world, work, settings, report);
  }
  if (report.solver.stopped) {
    work.solver.rng = pass_order;
    return std::nullopt;
  }
  for (std::size_t s = 0; s < repeated_times.size(); ++s) {
    result.stage_seconds[s] += repeated_times[s];
  }
  result.repeated_steps += repeated_steps;
  result.repeated_passes += repeated_passes;
  result.threaded_steps += report.solver.threaded ? 1 : 0;
  commit_step(world, work, settings, report);
  return report;
}

/// How the static solves after a step ended (run_simulation).
enum class StaticChecks {
  GoOn,     ///< none adopted: the run goes on
  Blocked,  ///< one was adopted: the run ends blocked
  Stopped,  ///< one was cut short by the stop request: asked again when the run continues
  /// the packing rests but stays out of balance: the run ends not blocked
  /// (RunResult::not_blocked says why)
  Unbalanced,
};

/// A static solve on a copy of the run's state: adopted (world and work replace the run's)
/// only when it ends the run.
struct RestSolve {
  World world;
  StepWorkspace work;
  StepReport report;
};

/// One call of run_simulation: the loop over steps, the accounting of each, and the static
/// solves that decide whether the packing is blocked.
class RunLoop {
 public:
  RunLoop(World& world, StepWorkspace& work, const StepSettings& settings, const RunConfig& run,
          RunState& state, const StepObserver& observer, const StopRequest& stop_requested)
      : world_(world),
        work_(work),
        settings_(settings),
        run_(run),
        state_(state),
        result_(state.result),
        observer_(observer),
        stop_requested_(stop_requested),
        start_(std::chrono::steady_clock::now()),
        adaptive_(settings.solver.time_step.adaptive),
        budget_(run.until_blocked ? run.max_duration : run.duration),
        // a fixed Δt: the step count from the budget, so round-off in t never adds or drops
        // a step; an adaptive Δt: until the simulated time has reached the budget
        max_steps_(adaptive_
                       ? std::numeric_limits<std::int64_t>::max()
                       : static_cast<std::int64_t>(std::llround(budget_ / settings.solver.dt))),
        current_(settings),
        load_(resting_load(world, settings.laws.spheres.cohesion_force)),
        // the grain volume is constant: computed once for the porosity check of every step
        fault_limits_{run.max_overlap, grain_volume(world.bodies)},
        smallest_radius_(world.bodies.min_radius()) {
    if (!state.started) {
      state.started = true;
      state.start_time = world.time;
      state.dt = settings.solver.dt;
      state.result.energy_start.piston_height = world.walls.piston.height;
      state.result.energy_start.kinetic_energy = kinetic_energy(world);
      state.result.energy_start.height_moment = height_moment(world);
    }
    // long solves (a static solve of 20 000 passes) ask the stop request after every pass
    current_.solver.stop_request = stop_requested ? &stop_requested : nullptr;
    if (run.until_blocked && !state.detector)
      state.detector.emplace(run.blocked, settings.solver.dt);
  }

  RunResult run() {
    // a run stopped inside a static solve of its last step: that solve first
    if (result_.steps > 0) {
      const StaticChecks pending = static_checks();
      if (pending == StaticChecks::Stopped) result_.interrupted = true;
      if (pending != StaticChecks::GoOn) return finish();
    }
    // result.steps counts the steps of every call, so k continues where a saved run stopped
    for (std::int64_t k = result_.steps; k < max_steps_ && !budget_spent(); ++k) {
      if (!advance()) break;
      // not after the last step: a run whose steps are all done is complete, not interrupted
      const bool last_step = k + 1 >= max_steps_ || budget_spent();
      if (!last_step && stop_requested_ && stop_requested_()) {
        result_.interrupted = true;
        break;
      }
    }
    return finish();
  }

 private:
  [[nodiscard]] double elapsed() const { return world_.time - state_.start_time; }

  [[nodiscard]] bool budget_spent() const {
    return adaptive_ && elapsed() >= budget_ * (1.0 - 1e-12);
  }

  [[nodiscard]] double fraction_done() const {
    return adaptive_ ? std::min(1.0, elapsed() / budget_)
                     : static_cast<double>(result_.steps) / static_cast<double>(max_steps_);
  }

  RunResult finish() {
    result_.wall_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return result_;
  }

  /// One step and what follows it; false when the run ends here (stopped inside the solve,
  /// a fault, blocked, or stopped inside a static solve).
  bool advance() {
    current_.solver.dt = state_.dt;
    const std::optional<StepReport> report =
        step_unless_stopped(world_, work_, current_, adaptive_, result_);
    if (!report) {  // stopped inside the solve: the state is the one after the step before
      result_.interrupted = true;
      return false;
    }
    account(*report);
    if (adaptive_) state_.dt = current_.solver.dt;  // a repeated step goes on from its shorter Δt
    if (state_.detector)
      state_.detector->update(world_, result_.last.diagnostics, current_.solver.dt);
    if (observer_) observer_(world_, result_.last, fraction_done());
    // a state no physical run reaches ends the run here, before any test reads it
    result_.fault = find_fault(world_, work_.contacts, result_.last.diagnostics, fault_limits_);
    if (result_.fault) return false;
    // the next Δt before the static solves: they leave the World as it is unless they end
    // the run, so it is the same either way, and a run stopped inside one has it already
    if (adaptive_) {
      // the spheres' fastest surface as integrate() measured it
      const SurfaceMotion motion =
          surface_motion(world_, result_.last.diagnostics.largest_surface_speed, smallest_radius_);
      state_.dt = next_time_step(settings_.solver.time_step, current_.solver.dt, motion,
                                 result_.last.diagnostics.max_cohesive_opening_speed,
                                 settings_.laws, settings_.solver.skin);
    }
    const StaticChecks checks = static_checks();
    if (checks == StaticChecks::Stopped) result_.interrupted = true;
    return checks == StaticChecks::GoOn;
  }

  void account(const StepReport& report) {
    RunResult& r = result_;
    r.last = report;
    r.min_dt = r.steps == 0 ? report.dt : std::min(r.min_dt, report.dt);
    r.max_dt = std::max(r.max_dt, report.dt);
    ++r.steps;
    r.total_passes += report.solver.passes;
    if (!report.solver.converged) ++r.capped_steps;
    r.max_overlap_seen = std::max(r.max_overlap_seen, report.diagnostics.max_overlap);
    r.max_cohesive_opening_per_range = std::max(r.max_cohesive_opening_per_range,
                                                report.diagnostics.max_cohesive_opening_per_range);
    // the first step's bonds are the packing's at the start, not changes of the run
    if (r.steps == 1) {
      // the step's contacts, built on the gaps the run started from
      r.energy_start.cohesive_energy = cohesive_energy(work_.contacts, settings_.laws);
    } else {
      r.bonds += report.diagnostics.bonds;
    }
    for (std::size_t s = 0; s < r.stage_seconds.size(); ++s) r.stage_seconds[s] += report.times[s];
  }

  /// The static solve on a copy, used by both tests below. The run's own step scratch is freed
  /// first (release_step_scratch): the copy's solve builds its own, and the two sets side by
  /// side were the peak of a run's memory (a 16 240-sphere compaction: 78.6 MB against 41.3 MB
  /// for steps of its blocked packing). A run that goes on rebuilds its scratch in the next
  /// step, with the same bits.
  [[nodiscard]] RestSolve solve_copy_at_rest() {
    release_step_scratch(work_);
    RestSolve rest{world_, work_, {}};
    rest.report = solve_at_rest(rest.world, rest.work, current_, run_.blocked);
    return rest;
  }

  /// The run ends blocked on `rest`. The static final solve is a measurement, not a step of
  /// the dynamics: reported as accuracy.final_solve, outside the step and pass counts (its
  /// time is in stage_seconds).
  StaticChecks adopt(RestSolve&& rest, double fraction) {
    world_ = std::move(rest.world);
    work_ = std::move(rest.work);
    result_.blocked = true;
    result_.last = rest.report;
    for (std::size_t s = 0; s < result_.stage_seconds.size(); ++s) {
      result_.stage_seconds[s] += rest.report.times[s];
    }
    result_.final_solve = rest.report.solver;
    if (observer_) observer_(world_, result_.last, fraction);
    return StaticChecks::Blocked;
  }

  /// Blocked by the window's tests: the packing is measured on a static solve of a copy,
  /// and adopted when that solve is in balance (balance_problem); otherwise the run goes on
  /// unchanged and the test is repeated a window later. A packing whose static solve is still
  /// out of balance after kMaxDeferredWindows windows ends the run not blocked, with the
  /// reason (without the bound such a run could go on to max_duration; before, it was
  /// reported blocked).
  StaticChecks check_blocked_window(double fraction) {
    RestSolve rest = solve_copy_at_rest();
    if (rest.report.solver.stopped) return StaticChecks::Stopped;
    state_.last_rest_check = world_.time;
    const std::optional<std::string> problem =
        balance_problem(rest.world, rest.work.contacts, rest.report, run_.blocked, load_);
    if (!problem) return adopt(std::move(rest), fraction);
    ++result_.unbalanced_rest_solves;
    if (state_.deferred_windows >= kMaxDeferredWindows) {
      result_.not_blocked = fmt::format(
          "the packing came to rest, but its static solve was out of balance in {} blocked "
          "windows: {}",
          kMaxDeferredWindows + 1, *problem);
      return StaticChecks::Unbalanced;
    }
    ++state_.deferred_windows;
    return StaticChecks::GoOn;
  }

  /// At rest for a whole window, but the window mean of the force imbalance is above its
  /// threshold: that mean is of the dynamic steps' forces, and noise the solver leaves in
  /// them can keep it there for good (measured: a 100-sphere packing at (μt, μn) = (1, 0)
  /// whose freely spinning spheres kept the mean at ≈ 0.02 until max_duration, 5 000 t0).
  /// So the balance is tested on a static solve of a copy instead, once per window: if the
  /// packing at rest carries the load with every sphere in balance, it is blocked;
  /// otherwise the run goes on unchanged.
  StaticChecks probe_balance(double fraction) {
    const auto probe_start = std::chrono::steady_clock::now();
    RestSolve probe = solve_copy_at_rest();
    const SolverStats& solver = probe.report.solver;
    if (solver.stopped) return StaticChecks::Stopped;
    state_.last_probe = world_.time;
    ++result_.probes;
    result_.probe_passes += solver.passes;
    result_.probe_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - probe_start).count();
    // an unconverged static solve says nothing about the balance, and the next would cost
    // as much again: stop probing and leave the run to the window mean
    if (!solver.converged) state_.probing = false;
    // (!(x < bound): a NaN imbalance is not in balance, as before)
    if (!solver.converged ||
        !(probe.report.diagnostics.piston_imbalance < run_.blocked.force_balance)) {
      return StaticChecks::GoOn;
    }
    if (balance_problem(probe.world, probe.work.contacts, probe.report, run_.blocked, load_)) {
      ++result_.unbalanced_rest_solves;
      return StaticChecks::GoOn;
    }
    result_.blocked_by_probe = true;
    return adopt(std::move(probe), fraction);
  }

  /// The static solves after a step, on copies. Their conditions are read from the state
  /// (the detector's memory, the times of the last solves), and a solve counts only once it
  /// has ended: a run stopped inside one asks the same question again first thing when it
  /// is continued, as a run never stopped asked it after that step.
  StaticChecks static_checks() {
    const std::optional<BlockedStateDetector>& detector = state_.detector;
    if (!detector) return StaticChecks::GoOn;
    const double fraction = fraction_done();
    const bool blocked = detector->blocked();
    if (blocked && detector->window_complete(world_.time - state_.last_rest_check)) {
      const StaticChecks checked = check_blocked_window(fraction);
      if (checked != StaticChecks::GoOn) return checked;
    }
    if (!blocked && state_.probing && detector->at_rest_for_window() &&
        detector->window_complete(world_.time - state_.last_probe)) {
      return probe_balance(fraction);
    }
    return StaticChecks::GoOn;
  }

  World& world_;
  StepWorkspace& work_;
  const StepSettings& settings_;
  const RunConfig& run_;
  RunState& state_;
  RunResult& result_;
  const StepObserver& observer_;
  const StopRequest& stop_requested_;
  std::chrono::steady_clock::time_point start_;
  bool adaptive_;
  double budget_;
  std::int64_t max_steps_;
  StepSettings current_;  ///< with the Δt of the step about to run
  double load_;
  FaultLimits fault_limits_;
  double smallest_radius_;  ///< the radii are constant: the next Δt's length, found once
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
  if (state.result.blocked) return state.result;  // a finished run has nothing left to do
  state.result.interrupted = false;               // a resumed run goes on
  RunLoop loop(world, work, settings, run, state, observer, stop_requested);
  return loop.run();
}

}  // namespace cdpowder
