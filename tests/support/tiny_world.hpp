// tiny_world.hpp — small scenes for tests in one expression, defined once and shared
// by the tests (and the benchmarks' support code builds on the same engine calls).
#pragma once

#include "cdpowder/model/world.hpp"
#include "cdpowder/solver/settings.hpp"
#include "cdpowder/solver/step.hpp"

namespace cdpowder::testing {

/// A world and the settings to step it, with a workspace that persists between steps.
struct TinyScene {
  World world;
  StepSettings settings;
  StepWorkspace work{1};

  /// Periodic cell lx × ly, no walls, no gravity; μ = 0.3, μ_t = μ_n = 0, F_coh = 1,
  /// d_coh = 0.01, Δt = 0.01, a tight tolerance so tests see converged forces.
  TinyScene(double lx, double ly);

  /// Adds a sphere of radius r (density 1) and returns its index.
  BodyIndex add(const Vec3& centre, double r = 1.0, bool fixed = false);

  /// Runs n steps, returns the report of the last one.
  StepReport run(int steps);

  /// Contact action between spheres a < b after the last step (zero if none).
  [[nodiscard]] ContactAction pair_action(BodyIndex a, BodyIndex b) const;

  /// Contact action of sphere i with a wall after the last step (zero if none).
  [[nodiscard]] ContactAction wall_action(BodyIndex i, WallKind wall) const;
};

/// Total linear momentum Σ m v (spheres only) [ρR⁴/t0].
Vec3 total_momentum(const Bodies& bodies);

/// Total angular momentum about the origin Σ (r × m v + I ω) [ρR⁵/t0].
Vec3 total_angular_momentum(const Bodies& bodies);

}  // namespace cdpowder::testing
