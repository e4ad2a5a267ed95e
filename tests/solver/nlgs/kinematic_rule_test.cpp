// The kinematic stopping rule (SolverSettings::kinematic_tolerance, physics.md §7.3): its
// measure on known velocities, and on the (0,0) compaction front, where the force residual
// stalls, that it stops a step far sooner with end velocities the fully converged step
// confirms.
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/solver/nlgs/kinematic_change.hpp"
#include "cdpowder/solver/nlgs/nlgs.hpp"
#include "cdpowder/solver/step.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace cdpowder {
namespace {

SphereVelocity sphere_of_radius(double radius, double dt) {
  const double mass = 4.0 / 3.0 * 3.141592653589793 * radius * radius * radius;
  SphereVelocity s;
  s.dt_inverse_mass = dt / mass;
  s.dt_inverse_inertia = dt / (0.4 * mass * radius * radius);
  return s;
}

TEST(KinematicChange, MeasuresTheSweepsLargestSurfaceChangeAndTheRmsSurfaceSpeed) {
  const double dt = 0.01;
  VelocityCache cache;
  cache.spheres = {sphere_of_radius(1.0, dt), sphere_of_radius(2.0, dt)};
  cache.spheres[1].linear = Vec3(0.0, 3e-3, 0.0);
  KinematicChange change;
  change.begin_step(cache);
  PassMotion motion = change.after_pass(cache, true);
  EXPECT_EQ(motion.largest_change, 0.0);
  EXPECT_NEAR(motion.rms_surface_speed, std::sqrt(9e-6 / 2), 1e-18);

  cache.spheres[0].linear = Vec3(3e-4, 0.0, 4e-4);  // u(Δv, Δω) = 5e-4
  cache.spheres[1].angular = Vec3(0.0, 0.0, 4e-4);  // R |Δω| = 8e-4
  cache.piston_velocity = -1e-3;
  motion = change.after_pass(cache, true);
  EXPECT_NEAR(motion.largest_change, 8e-4, 1e-15);
  EXPECT_NEAR(motion.rms_surface_speed, std::sqrt((25e-8 + 9e-6 + 64e-8) / 2), 1e-15);
  EXPECT_EQ(motion.piston_change, 1e-3);

  // the next sweep starts from the velocities the last one left; without the speed asked
  // for, the RMS speed is not summed
  motion = change.after_pass(cache, false);
  EXPECT_EQ(motion.largest_change, 0.0);
  EXPECT_EQ(motion.piston_change, 0.0);
  EXPECT_EQ(motion.rms_surface_speed, 0.0);

  // a change between sweeps (the mixing) is not the next sweep's once it is reported
  cache.spheres[0].linear = Vec3(0.0, 0.0, 0.0);
  cache.piston_velocity = -2e-3;
  change.velocities_changed(cache);
  motion = change.after_pass(cache, true);
  EXPECT_EQ(motion.largest_change, 0.0);
  EXPECT_EQ(motion.piston_change, 0.0);
}

// The RMS change (solver.kinematic_norm = "rms"): √(mean over the spheres of u(Δv, Δω)²).
TEST(KinematicChange, MeasuresTheRmsSurfaceChangeWhenAskedFor) {
  const double dt = 0.01;
  VelocityCache cache;
  cache.spheres = {sphere_of_radius(1.0, dt), sphere_of_radius(2.0, dt)};
  KinematicChange change;
  change.begin_step(cache, {}, true);
  cache.spheres[0].linear = Vec3(3e-4, 0.0, 4e-4);  // u(Δv, Δω) = 5e-4
  cache.spheres[1].angular = Vec3(0.0, 0.0, 4e-4);  // R |Δω| = 8e-4
  const PassMotion motion = change.after_pass(cache, false);
  EXPECT_NEAR(motion.largest_change, 8e-4, 1e-15);
  EXPECT_NEAR(motion.rms_change, std::sqrt((25e-8 + 64e-8) / 2), 1e-15);
}

TEST(KinematicChange, AFixedSphereCountsOnlyItsTranslation) {
  VelocityCache cache;
  cache.spheres.resize(1);  // Δt/m = Δt/I = 0
  KinematicChange change;
  change.begin_step(cache);
  cache.spheres[0].angular = Vec3(1.0, 0.0, 0.0);
  EXPECT_EQ(change.after_pass(cache, true).largest_change, 0.0);
}

// The pass runs in lanes (2 or 4 spheres side by side, blocks of 4): for every count of
// spheres around the block size, on either instruction set, it gives the bits of the plain
// loop over the spheres (Eigen's squaredNorm, std::max, the sum in index order).
TEST(KinematicChange, TheLanesGiveTheBitsOfOneSphereAtATime) {
  const double dt = 0.013;
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    const bool avx2 = isa == lanes::Isa::Avx2;
    for (std::size_t n = 1; n <= 9; ++n) {
      VelocityCache cache;
      for (std::size_t i = 0; i < n; ++i) {
        cache.spheres.push_back(sphere_of_radius(0.7 + 0.11 * static_cast<double>(i), dt));
      }
      const auto fill = [&](double phase) {
        for (std::size_t i = 0; i < n; ++i) {
          const double x = phase + 1.7 * static_cast<double>(i);
          cache.spheres[i].linear = Vec3(std::sin(x), std::cos(3 * x), 1e-3 * x);
          cache.spheres[i].angular = Vec3(std::cos(x) / 7, -x, std::sin(5 * x));
        }
      };
      fill(0.3);
      const VelocityCache before = cache;
      KinematicChange change;
      KinematicChange change_alone;  // the pass without the RMS speed
      KinematicChange change_rms;    // with the RMS change (solver.kinematic_norm = "rms")
      change.begin_step(cache);
      change_alone.begin_step(cache);
      change_rms.begin_step(cache, {}, true);
      fill(1.1);
      const PassMotion motion = change.after_pass(cache, true);
      const PassMotion motion_alone = change_alone.after_pass(cache, false);
      const PassMotion motion_rms = change_rms.after_pass(cache, false);
      double largest_sq = 0.0;
      double sum_sq = 0.0;
      double change_sum_sq = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const SphereVelocity& s = cache.spheres[i];
        const SphereVelocity& was = before.spheres[i];
        const double r_sq = 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia;
        const double change_sq =
            (s.linear - was.linear).squaredNorm() + r_sq * (s.angular - was.angular).squaredNorm();
        largest_sq = std::max(largest_sq, change_sq);
        change_sum_sq += change_sq;
        sum_sq += s.linear.squaredNorm() + r_sq * s.angular.squaredNorm();
      }
      EXPECT_EQ(motion.largest_change, std::sqrt(largest_sq)) << n << " spheres, avx2 " << avx2;
      EXPECT_EQ(motion_alone.largest_change, std::sqrt(largest_sq))
          << n << " spheres, avx2 " << avx2;
      EXPECT_EQ(motion.rms_surface_speed, std::sqrt(sum_sq / static_cast<double>(n)))
          << n << " spheres, avx2 " << avx2;
      EXPECT_EQ(motion.rms_change, 0.0) << "not asked for";
      EXPECT_EQ(motion_rms.largest_change, std::sqrt(largest_sq));
      EXPECT_EQ(motion_rms.rms_change, std::sqrt(change_sum_sq / static_cast<double>(n)))
          << n << " spheres, avx2 " << avx2;
    }
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

/// Solves the contact problem of the step after the saved (0,0) compaction front
/// (t = 350 t0, plus one step for a warm start from a front step) with `solver`, its visiting
/// order drawn from `order_seed`; returns the solver's report and leaves the end velocities
/// in `velocities`.
SolverStats solve_front_step(const SolverSettings& solver, std::uint64_t order_seed,
                             VelocityCache& velocities) {
  const std::filesystem::path file =
      std::filesystem::path(CDPOWDER_SOURCE_DIR) / "bench/fixtures/paper_front_mu00_t350.cdps";
  SavedRun saved = load_state(file);
  const Scene scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
  World world;
  StepWorkspace work(scene.step.solver.seed);
  RunState run;
  restore_run(std::move(saved), scene.run, scene.step.solver.dt, world, work, run);
  step(world, work, scene.step);
  // stages 1 and 2 of step(), then the solver with the settings under test
  begin_step(world, work, scene.step);
  work.solver.rng = make_rng(order_seed, RngStream::PassOrder);
  const SolverStats stats = solve_nlgs(work.contacts, work.velocities, solver,
                                       scene.step.laws.spheres.cohesion_force, work.solver);
  velocities = work.velocities;
  return stats;
}

/// The largest error of a sphere's surface velocity u = √(|v|² + R²|ω|²) against `exact`, over
/// the RMS surface speed of `exact`, and the piston's error over its speed.
struct RelativeError {
  double spheres = 0.0;
  double piston = 0.0;
};

RelativeError relative_error(const VelocityCache& approximate, const VelocityCache& exact) {
  const double radius = 1.0;  // the fixture's deposit is monodisperse
  const auto surface = [&](const Vec3& v, const Vec3& w) {
    return std::sqrt(v.squaredNorm() + radius * radius * w.squaredNorm());
  };
  double largest = 0.0;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < exact.spheres.size(); ++i) {
    const SphereVelocity& a = approximate.spheres[i];
    const SphereVelocity& b = exact.spheres[i];
    largest = std::max(largest, surface(a.linear - b.linear, a.angular - b.angular));
    sum_sq += std::pow(surface(b.linear, b.angular), 2);
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(exact.spheres.size()));
  return {largest / rms, std::abs(approximate.piston_velocity - exact.piston_velocity) /
                             std::abs(exact.piston_velocity)};
}

/// The kinematic rule on a stalled front step, solved with `kernel` in a visiting order drawn
/// from `order_seed`: a converged solve, the paper example's capped solve (tolerance 1e-3,
/// 200 sweeps) and the same with the kinematic rule at κ, and the errors of the last two.
struct FrontStepErrors {
  SolverStats converged, capped, early;
  RelativeError capped_error, early_error;
};

FrontStepErrors kinematic_rule_on_the_front_step(PassKernel kernel, std::uint64_t order_seed,
                                                 double kappa) {
  FrontStepErrors out;
  // ten times tighter than the paper example; the tail of such a solve takes 640–2 240 passes
  // over the ten solves of the test (two kernels, five orders), so it may take 4 000
  SolverSettings converged_settings;
  converged_settings.kernel = kernel;
  converged_settings.tolerance = 1e-4;
  converged_settings.max_passes = 4000;
  VelocityCache converged;
  out.converged = solve_front_step(converged_settings, order_seed, converged);

  SolverSettings paper = converged_settings;
  paper.tolerance = 1e-3;
  paper.max_passes = 200;
  VelocityCache capped;
  out.capped = solve_front_step(paper, order_seed, capped);

  SolverSettings kinematic = paper;
  kinematic.kinematic_tolerance = kappa;
  VelocityCache early;
  out.early = solve_front_step(kinematic, order_seed, early);
  out.capped_error = relative_error(capped, converged);
  out.early_error = relative_error(early, converged);
  return out;
}

// Where the rule stops a single step depends on the rounding of every sweep before it (a
// change in the last bit of the mixing's sums moved it from 45 to 21 sweeps), so the rule is
// judged over five visiting orders for each kernel: every solve stops early on its own
// estimate, and the mean error is held against the paper example's capped step (200 sweeps).
// Measured (κ = 1e-4, five orders): the scalar kernel stops after 21–42 sweeps, largest
// sphere error 1.18e-3 of the RMS surface speed on average (0.75–1.39e-3) against the capped
// step's 4.9e-4, piston 3.1e-6 against 2.4e-6 of its speed; the coloured kernel after 24–51
// sweeps, 1.01e-3 (0.65–1.27e-3) against 4.1e-4, piston 4.9e-6 against 2.2e-6. The estimate
// is optimistic (true error ≈ 10 κ), as the force residual's is (physics.md §7.3), so the rule
// is judged against what the capped steps leave; whole runs are judged by the accuracy gate
// (docs/performance.md), which runs with the rule pass.
TEST(KinematicRule, StopsAStalledFrontStepEarlyAtTheAccuracyOfTheCappedStep) {
  const double kappa = 1e-4;
  for (const PassKernel kernel : {PassKernel::Scalar, PassKernel::Coloured}) {
    SCOPED_TRACE(kernel == PassKernel::Scalar ? "scalar kernel" : "coloured kernel");
    RelativeError early_mean;
    RelativeError capped_mean;
    const int orders = 5;
    for (std::uint64_t seed = 1; seed <= orders; ++seed) {
      const FrontStepErrors e = kinematic_rule_on_the_front_step(kernel, seed, kappa);
      ASSERT_TRUE(e.converged.converged);
      ASSERT_FALSE(e.capped.converged) << "the force residual stalls on this step";
      EXPECT_TRUE(e.early.converged);
      EXPECT_LE(e.early.kinematic_error, kappa);
      EXPECT_LE(e.early.piston_speed_error, kappa);
      EXPECT_LT(3 * e.early.passes, e.capped.passes);
      early_mean.spheres += e.early_error.spheres / orders;
      early_mean.piston += e.early_error.piston / orders;
      capped_mean.spheres += e.capped_error.spheres / orders;
      capped_mean.piston += e.capped_error.piston / orders;
    }
    EXPECT_LT(early_mean.spheres, 3 * capped_mean.spheres);
    EXPECT_LT(early_mean.spheres, 15 * kappa);
    EXPECT_LT(early_mean.piston, 5 * capped_mean.piston);
  }
}

}  // namespace
}  // namespace cdpowder
