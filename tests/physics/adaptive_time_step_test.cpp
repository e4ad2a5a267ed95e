// The adaptive time step (solver/time_step_control.hpp, run/run_loop.cpp) on the
// quick example's (0, 0) compaction, the case whose cohesive contacts open fastest: every
// step keeps the opening of §6.4 within its bound, and Δt moves between its bounds. dt_max is
// 0.05 here, above the default, so that steps open contacts too far and are repeated.
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/setup/scene_setup.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace cdpowder::testing {
namespace {

TEST(AdaptiveTimeStep, KeepsEveryCohesiveOpeningWithinItsBound) {
  SceneReadOptions options;
  options.compaction = true;
  const Scene scene =
      read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml",
                 {"contact.mu_roll=0", "contact.mu_twist=0", "solver.adaptive_dt=true",
                  "run.max_duration=100", "solver.dt_max=0.05"},
                 options);
  World world = make_world(scene);
  StepWorkspace work(scene.step.solver.seed);
  double largest_step_opening = 0.0;
  const RunResult result = run_simulation(
      world, work, scene.step, scene.run, [&](const World&, const StepReport& r, double) {
        largest_step_opening =
            std::max(largest_step_opening, r.diagnostics.max_cohesive_opening_per_range);
      });
  const TimeStepControl& control = scene.step.solver.time_step;
  EXPECT_LE(largest_step_opening, control.max_opening_per_step);
  EXPECT_LE(result.max_cohesive_opening_per_range, control.max_opening_per_step);
  EXPECT_GE(result.min_dt, control.dt_min);
  EXPECT_LE(result.max_dt, control.dt_max);
  EXPECT_EQ(result.max_dt, control.dt_max);        // the quiet phases reach dt_max
  EXPECT_LT(result.min_dt, 0.5 * control.dt_max);  // and breaking contacts shorten it
  // 100 t0 of simulated time, to the step
  EXPECT_NEAR(world.time, 100.0, control.dt_max);
  EXPECT_GE(world.time, 100.0 * (1.0 - 1e-12));
}

}  // namespace
}  // namespace cdpowder::testing
