// run_loop.cpp — the time loop with its stop conditions.
#include "cdpowder/experiment/run_loop.hpp"

#include "cdpowder/experiment/blocked_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace cdpowder {

RunResult run_simulation(World& world, StepWorkspace& work, const StepSettings& settings,
                         const RunConfig& run, const StepObserver& observer,
                         const StopRequest& stop_requested) {
  RunResult result;
  const auto start = std::chrono::steady_clock::now();
  const double dt = settings.solver.dt;
  const double budget = run.until_blocked ? run.max_duration : run.duration;
  // step count from the budget, so round-off in t never adds or drops a step
  const auto max_steps = static_cast<std::int64_t>(std::llround(budget / dt));
  std::optional<BlockedStateDetector> detector;
  if (run.until_blocked) detector.emplace(run.blocked, dt);

  const auto account = [&](const StepReport& report) {
    result.last = report;
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

  for (std::int64_t k = 0; k < max_steps; ++k) {
    account(step(world, work, settings));
    const double fraction = static_cast<double>(k + 1) / static_cast<double>(max_steps);
    const bool blocked = detector && detector->update(world, result.last.diagnostics);
    if (observer) observer(world, result.last, fraction);
    if (blocked) {
      result.blocked = true;
      // The packing is at rest: measure it in static equilibrium. Its residual velocities
      // are solver noise, and the piston turns them into forces of M_P V_P/Δt (at
      // V_P = 1e-5 R/t0 and Δt = 0.01 t0 on the paper's piston, 1 F_coh, more than half
      // the load F), so one more step starts from rest and is solved to the final
      // tolerance; the stress is measured on its forces.
      for (Vec3& v : world.bodies.velocity) v.setZero();
      for (Vec3& w : world.bodies.angular_velocity) w.setZero();
      world.walls.piston.velocity = 0.0;
      StepSettings final_settings = settings;
      final_settings.solver.tolerance = run.blocked.final_tolerance;
      final_settings.solver.max_sweeps = run.blocked.final_max_sweeps;
      final_settings.solver.min_sweeps =
          std::min(settings.solver.min_sweeps, run.blocked.final_max_sweeps);
      // a measurement, not a step of the dynamics: reported as accuracy.final_solve, outside
      // the step and sweep counts (its time is in stage_seconds)
      result.last = step(world, work, final_settings);
      for (std::size_t s = 0; s < result.stage_seconds.size(); ++s) {
        result.stage_seconds[s] += result.last.times[s];
      }
      result.final_solve = result.last.solver;
      if (observer) observer(world, result.last, fraction);
      break;
    }
    if (stop_requested && stop_requested()) {
      result.interrupted = true;
      break;
    }
  }
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace cdpowder
