// The time loop's stop at the blocked state (experiment/run_loop.hpp, physics.md §9).
#include "cdpowder/experiment/run_loop.hpp"

#include "cdpowder/experiment/blocked_state.hpp"
#include "support/tiny_world.hpp"

#include <gtest/gtest.h>

namespace cdpowder::testing {
namespace {

// A column of spheres on the bottom wall with the piston resting on it. One plain NLGS
// sweep per step leaves the column's forces far from converged (the piston mode needs
// ~10⁴ sweeps, tests/physics/piston_column_test.cpp), so the dynamic steps' force
// imbalance stays large while nothing moves.
TinyScene noisy_column() {
  TinyScene s(5.0, 5.0);
  s.world.walls.bottom.enabled = true;
  s.world.walls.piston.enabled = true;
  s.world.walls.piston.mass = 1000.0;
  s.world.walls.piston.force = 0.7;
  for (int k = 0; k < 12; ++k) s.add(Vec3(2.5, 2.5, 1.0 + 2.0 * k));
  s.world.walls.piston.height = 24.0;
  s.settings.solver.acceleration_depth = 0;
  s.settings.solver.min_sweeps = 1;
  s.settings.solver.max_sweeps = 1;
  return s;
}

RunConfig until_blocked() {
  RunConfig run;
  run.until_blocked = true;
  run.max_duration = 20.0;   // 2 000 steps
  run.blocked.window = 0.5;  // 50 steps
  run.blocked.piston_speed = 1e-2;
  run.blocked.sphere_speed = 1e-2;
  run.blocked.height_change = 1e-2;
  run.blocked.force_balance = 1e-3;
  run.blocked.final_tolerance = 1e-10;
  run.blocked.final_max_sweeps = 200000;
  return run;
}

// At rest for a whole window but with the window mean of the dynamic imbalance above its
// threshold, the run tests the balance on a static solve and stops there: blocked, at
// the window's last step, with the piston balanced to the final tolerance.
TEST(RunLoop, ARestingPackingWithNoisyDynamicForcesBlocksOnTheStaticProbe) {
  TinyScene s = noisy_column();
  const RunConfig run = until_blocked();
  const RunResult result = run_simulation(s.world, s.work, s.settings, run, {});
  ASSERT_TRUE(result.blocked);
  ASSERT_TRUE(result.final_solve.has_value());
  EXPECT_TRUE(result.final_solve->converged);
  EXPECT_LT(result.last.diagnostics.piston_imbalance, 1e-6);
  EXPECT_EQ(result.steps, 50);  // the first step at which a whole window was at rest
  EXPECT_EQ(result.probes, 1);
  EXPECT_TRUE(result.blocked_by_probe);

  // the same steps again with the detector alone: a whole window at rest, and a window
  // mean of the dynamic imbalance that the standard test would not have accepted
  TinyScene again = noisy_column();
  BlockedStateDetector detector(run.blocked, again.settings.solver.dt);
  for (std::int64_t k = 0; k < result.steps; ++k) {
    const StepReport report = step(again.world, again.work, again.settings);
    EXPECT_FALSE(detector.update(again.world, report.diagnostics));
  }
  EXPECT_TRUE(detector.at_rest_for_window());
  EXPECT_GT(detector.mean_force_imbalance(), run.blocked.force_balance);
}

// A probe that fails leaves the run as it was: the same steps, and the same state, as a
// run whose probes are never tried (force_balance so strict that no probe can pass), and
// the same next step (nothing of the probe stays in the solver's stream or warm start).
TEST(RunLoop, AFailedProbeLeavesTheRunUnchanged) {
  RunConfig run = until_blocked();
  run.max_duration = 2.0;              // 200 steps: probes at steps 50, 100, 150, 200
  run.blocked.force_balance = 1e-300;  // no probe passes
  TinyScene probed = noisy_column();
  int observed = 0;
  const RunResult result =
      run_simulation(probed.world, probed.work, probed.settings, run,
                     [&](const World&, const StepReport&, double) { ++observed; });
  EXPECT_FALSE(result.blocked);
  EXPECT_EQ(result.steps, 200);
  EXPECT_EQ(result.probes, 4);
  EXPECT_GT(result.probe_sweeps, 0);
  EXPECT_EQ(observed, 200);  // probes are not steps

  TinyScene plain = noisy_column();
  std::int64_t plain_sweeps = 0;
  for (int k = 0; k < 200; ++k)
    plain_sweeps += step(plain.world, plain.work, plain.settings).solver.sweeps;
  EXPECT_EQ(result.total_sweeps, plain_sweeps);
  const auto expect_same = [](const World& a, const World& b) {
    EXPECT_EQ(a.bodies.position, b.bodies.position);
    EXPECT_EQ(a.bodies.velocity, b.bodies.velocity);
    EXPECT_EQ(a.bodies.angular_velocity, b.bodies.angular_velocity);
    EXPECT_EQ(a.walls.piston.height, b.walls.piston.height);
    EXPECT_EQ(a.walls.piston.velocity, b.walls.piston.velocity);
  };
  expect_same(probed.world, plain.world);
  step(probed.world, probed.work, probed.settings);
  step(plain.world, plain.work, plain.settings);
  expect_same(probed.world, plain.world);
}

// A static solve that does not converge tells nothing about the balance: it does not block
// the run, and no further probe is tried.
TEST(RunLoop, AnUnconvergedProbeDoesNotBlockAndStopsTheProbing) {
  RunConfig run = until_blocked();
  run.max_duration = 2.0;
  run.blocked.final_max_sweeps = 1;
  TinyScene s = noisy_column();
  s.settings.solver.tolerance = 1e-12;
  const RunResult result = run_simulation(s.world, s.work, s.settings, run, {});
  EXPECT_EQ(result.probes, 1);
  EXPECT_FALSE(result.blocked_by_probe);
}

}  // namespace
}  // namespace cdpowder::testing
