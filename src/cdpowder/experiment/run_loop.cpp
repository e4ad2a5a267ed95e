// run_loop.cpp — the time loop with its stop conditions.
#include "cdpowder/experiment/run_loop.hpp"

#include "cdpowder/experiment/blocked_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

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
  BlockedStateDetector detector(run.blocked, dt);

  for (std::int64_t k = 0; k < max_steps; ++k) {
    result.last = step(world, work, settings);
    ++result.steps;
    result.total_sweeps += result.last.solver.sweeps;
    if (!result.last.solver.converged) ++result.capped_steps;
    result.max_overlap_seen =
        std::max(result.max_overlap_seen, result.last.diagnostics.max_overlap);
    result.max_cohesive_opening_per_range =
        std::max(result.max_cohesive_opening_per_range,
                 result.last.diagnostics.max_cohesive_opening_per_range);
    for (std::size_t s = 0; s < result.stage_seconds.size(); ++s) {
      result.stage_seconds[s] += result.last.times[s];
    }
    const bool blocked = run.until_blocked && detector.update(world, result.last.diagnostics);
    if (observer) {
      observer(world, result.last, static_cast<double>(k + 1) / static_cast<double>(max_steps));
    }
    if (blocked) {
      result.blocked = true;
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
