// The time loop's stop at the blocked state (run/run_loop.hpp, physics.md §9).
#include "cdpowder/run/run_loop.hpp"

#include "cdpowder/run/blocked_state.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/run/state_hash.hpp"
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
  s.settings.solver.min_passes = 1;
  s.settings.solver.max_passes = 1;
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
  run.blocked.final_max_passes = 200000;
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
  EXPECT_GT(result.probe_passes, 0);
  EXPECT_EQ(observed, 200);  // probes are not steps

  TinyScene plain = noisy_column();
  std::int64_t plain_sweeps = 0;
  for (int k = 0; k < 200; ++k)
    plain_sweeps += step(plain.world, plain.work, plain.settings).solver.passes;
  EXPECT_EQ(result.total_passes, plain_sweeps);
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
  run.blocked.final_max_passes = 1;
  TinyScene s = noisy_column();
  s.settings.solver.tolerance = 1e-12;
  const RunResult result = run_simulation(s.world, s.work, s.settings, run, {});
  EXPECT_EQ(result.probes, 1);
  EXPECT_FALSE(result.blocked_by_probe);
}

// The same column with forces converged at every step (the default tight tolerance), so
// the window's tests alone find the blocked state.
TinyScene quiet_column() {
  TinyScene s = noisy_column();
  s.settings.solver = TinyScene(5.0, 5.0).settings.solver;
  return s;
}

// Adds a free sphere beside the column, out of reach of it (minimum-image distance 2.5 R in
// y), pushed along x by a constant force [F_coh]: at rest by the kinematic tests for the
// first windows (it gains 0.24 f R/t0 per t0; the RMS over 13 spheres is 3.6 times less),
// but never in balance.
void add_pushed_sphere(TinyScene& s, double force) {
  const BodyIndex i = s.add(Vec3(0.5, 0.0, 12.0));
  s.world.bodies.external_force[i] = Vec3(force, 0.0, 0.0);
}

// A window at rest whose static solve shows a sphere out of balance is not the blocked
// state: the run goes on, and the check is repeated once per window, up to five times; the
// sixth is measured as it is (its gauges show the imbalance).
TEST(RunLoop, ASphereOutOfBalanceDefersTheBlockedState) {
  RunConfig run = until_blocked();
  run.max_duration = 2.0;  // 200 steps: checks at steps 50, 100, 150, 200 at most
  TinyScene pushed = quiet_column();
  add_pushed_sphere(pushed, 0.01);  // 0.01 F_coh against force_balance × F = 7e-4
  const RunResult result = run_simulation(pushed.world, pushed.work, pushed.settings, run, {});
  EXPECT_FALSE(result.blocked);
  EXPECT_EQ(result.steps, 200);
  EXPECT_GE(result.unbalanced_rest_solves, 1);
  EXPECT_LE(result.unbalanced_rest_solves, 4);
  EXPECT_EQ(result.probes, 0);

  run.max_duration = 10.0;
  TinyScene deferred = quiet_column();
  add_pushed_sphere(deferred, 0.01);
  const RunResult bounded =
      run_simulation(deferred.world, deferred.work, deferred.settings, run, {});
  // out of balance in the first window (50 steps) and 5 deferred ones: not blocked, and why
  // (it was reported blocked before)
  EXPECT_FALSE(bounded.blocked);
  EXPECT_FALSE(bounded.interrupted);
  EXPECT_EQ(bounded.unbalanced_rest_solves, 6);
  EXPECT_EQ(bounded.steps, 300);
  EXPECT_NE(bounded.not_blocked.find("out of balance in 6 blocked windows: a sphere stays out "
                                     "of balance at rest (largest net force 0.01 F_coh"),
            std::string::npos)
      << bounded.not_blocked;

  // the same scene with a push far below the tolerance blocks on the window, as before
  TinyScene nudged = quiet_column();
  add_pushed_sphere(nudged, 1e-6);
  const RunResult blocked = run_simulation(nudged.world, nudged.work, nudged.settings, run, {});
  ASSERT_TRUE(blocked.blocked);
  EXPECT_FALSE(blocked.blocked_by_probe);
  EXPECT_EQ(blocked.unbalanced_rest_solves, 0);
  EXPECT_EQ(blocked.steps, 50);
  EXPECT_LT(blocked.last.diagnostics.max_net_force, 1e-5);
}

// The probe's static solve must show every sphere in balance too, not only the piston.
TEST(RunLoop, ASphereOutOfBalanceKeepsTheProbeFromBlocking) {
  RunConfig run = until_blocked();
  run.max_duration = 2.0;
  TinyScene s = noisy_column();
  add_pushed_sphere(s, 0.05);
  const RunResult result = run_simulation(s.world, s.work, s.settings, run, {});
  EXPECT_FALSE(result.blocked);
  EXPECT_GE(result.probes, 1);
  EXPECT_EQ(result.unbalanced_rest_solves, result.probes);
  EXPECT_FALSE(result.blocked_by_probe);
}

// Stopped at any step, saved to a state file's bytes and continued in a fresh engine, a
// run takes the same decisions as one never stopped: deferred windows, probes and the
// blocked state (or its refusal) at the same steps, with the same final state.
TEST(RunLoop, ARunResumedFromItsStateFileTakesTheSameDecisions) {
  RunConfig run = until_blocked();
  run.max_duration = 10.0;
  const auto make = [] {
    TinyScene s = quiet_column();
    add_pushed_sphere(s, 0.01);  // five deferred windows, then not blocked at step 300
    return s;
  };
  TinyScene whole = make();
  const RunResult uninterrupted = run_simulation(whole.world, whole.work, whole.settings, run, {});
  ASSERT_FALSE(uninterrupted.blocked);
  ASSERT_FALSE(uninterrupted.not_blocked.empty());
  ASSERT_EQ(uninterrupted.unbalanced_rest_solves, 6);
  for (const std::int64_t stop_at : {1, 49, 50, 51, 175, 299}) {
    TinyScene first = make();
    RunState state;
    run_simulation(first.world, first.work, first.settings, run, state, {},
                   [&] { return state.result.steps == stop_at; });
    ASSERT_EQ(state.result.steps, stop_at);
    const std::string bytes = encode_state("", first.world, first.work, state);
    TinyScene resumed = make();
    RunState resumed_state;
    restore_run(decode_state(bytes, "memory"), run, resumed.settings.solver.dt, resumed.world,
                resumed.work, resumed_state);
    const RunResult result =
        run_simulation(resumed.world, resumed.work, resumed.settings, run, resumed_state, {});
    EXPECT_EQ(result.not_blocked, uninterrupted.not_blocked) << "stopped at " << stop_at;
    EXPECT_EQ(result.steps, uninterrupted.steps) << "stopped at " << stop_at;
    EXPECT_EQ(result.total_passes, uninterrupted.total_passes) << "stopped at " << stop_at;
    EXPECT_EQ(result.unbalanced_rest_solves, 6) << "stopped at " << stop_at;
    EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(whole.world, whole.work))
        << "stopped at " << stop_at;
  }

  // the probes' path: a noisy column blocked by the probe at step 50
  TinyScene noisy = noisy_column();
  const RunResult probed = run_simulation(noisy.world, noisy.work, noisy.settings, run, {});
  ASSERT_TRUE(probed.blocked_by_probe);
  for (const std::int64_t stop_at : {25, 49}) {
    TinyScene first = noisy_column();
    RunState state;
    run_simulation(first.world, first.work, first.settings, run, state, {},
                   [&] { return state.result.steps == stop_at; });
    TinyScene resumed = noisy_column();
    RunState resumed_state;
    restore_run(decode_state(encode_state("", first.world, first.work, state), "memory"), run,
                resumed.settings.solver.dt, resumed.world, resumed.work, resumed_state);
    const RunResult result =
        run_simulation(resumed.world, resumed.work, resumed.settings, run, resumed_state, {});
    EXPECT_TRUE(result.blocked_by_probe) << "stopped at " << stop_at;
    EXPECT_EQ(result.probes, probed.probes) << "stopped at " << stop_at;
    EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(noisy.world, noisy.work))
        << "stopped at " << stop_at;
  }
}

// A stop asked inside a static solve (a probe of up to 200 000 sweeps here) ends that solve
// on a sweep's output and the run at once, the solve not counted; continued from its state
// file, the run solves it again and ends as the run never stopped.
TEST(RunLoop, AStopInsideAStaticSolveIsSolvedAgainWhenTheRunContinues) {
  const RunConfig run = until_blocked();
  TinyScene whole = noisy_column();
  const RunResult uninterrupted = run_simulation(whole.world, whole.work, whole.settings, run, {});
  ASSERT_TRUE(uninterrupted.blocked_by_probe);
  ASSERT_GT(uninterrupted.last.solver.passes, 100);
  const std::int64_t probe_step = uninterrupted.steps;

  TinyScene first = noisy_column();
  RunState state;
  int polls = 0;  // the loop asks once after a step, the solver after every sweep
  const RunResult stopped =
      run_simulation(first.world, first.work, first.settings, run, state, {},
                     [&] { return state.result.steps == probe_step && ++polls == 100; });
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_FALSE(stopped.blocked);
  EXPECT_EQ(stopped.steps, probe_step);
  EXPECT_EQ(polls, 100);  // inside the probe: it has more than 100 sweeps
  EXPECT_EQ(stopped.probes, 0);
  EXPECT_EQ(stopped.probe_passes, 0);

  TinyScene resumed = noisy_column();
  RunState resumed_state;
  restore_run(decode_state(encode_state("", first.world, first.work, state), "memory"), run,
              resumed.settings.solver.dt, resumed.world, resumed.work, resumed_state);
  const RunResult result =
      run_simulation(resumed.world, resumed.work, resumed.settings, run, resumed_state, {});
  EXPECT_TRUE(result.blocked_by_probe);
  EXPECT_EQ(result.steps, uninterrupted.steps);
  EXPECT_EQ(result.probes, uninterrupted.probes);
  EXPECT_EQ(result.probe_passes, uninterrupted.probe_passes);
  ASSERT_TRUE(result.final_solve.has_value());
  EXPECT_EQ(result.final_solve->passes, uninterrupted.final_solve->passes);
  EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(whole.world, whole.work));
}

}  // namespace
}  // namespace cdpowder::testing
