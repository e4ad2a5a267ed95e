// kinematic_change.hpp — how much the last sweep changed the step's end velocities, against
// how fast the packing moves: the measures of the kinematic stopping rule
// (SolverSettings::kinematic_tolerance, physics.md §7.3).
#pragma once

#include "cdpowder/solver/velocity_cache.hpp"

#include <cmath>
#include <vector>

namespace cdpowder {

/// What one sweep did to the end velocities. A sphere's surface velocity is measured as
/// u = √(|v|² + R²|ω|²), within √2 of the fastest point of its surface |v| + R|ω|.
struct SweepMotion {
  double largest_change = 0.0;     ///< max over the spheres of u(Δv, Δω) [R/t0]
  double rms_surface_speed = 0.0;  ///< √(mean over the spheres of u(v, ω)²) after the sweep [R/t0]
  double piston_change = 0.0;      ///< |ΔV_P| [R/t0]
};

/// Takes the velocities before a sweep and compares them with the ones after it. Buffers are
/// kept from sweep to sweep and step to step (no allocation in steady state).
class KinematicChange {
 public:
  /// Remembers v*, ω*, V_P* before a sweep; on the first call of a step (`new_step`) also
  /// R² of every sphere, from the cache's Δt/m and Δt/I (solid sphere: I = 0.4 m R²).
  void before_sweep(const VelocityCache& velocities, bool new_step);

  /// The change since before_sweep, and the speeds now.
  [[nodiscard]] SweepMotion after_sweep(const VelocityCache& velocities) const;

 private:
  std::vector<SphereVelocity> start_;
  std::vector<double> radius_sq_;
  double piston_start_ = 0.0;
};

}  // namespace cdpowder
