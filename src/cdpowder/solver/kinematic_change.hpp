// kinematic_change.hpp — how much the last sweep changed the step's end velocities, against
// how fast the packing moves: the measures of the kinematic stopping rule
// (SolverSettings::kinematic_tolerance, physics.md §7.3).
#pragma once

#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/solver/velocity_cache.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cdpowder {

/// What one sweep did to the end velocities. A sphere's surface velocity is measured as
/// u = √(|v|² + R²|ω|²), within √2 of the fastest point of its surface |v| + R|ω|.
struct SweepMotion {
  double largest_change = 0.0;     ///< max over the spheres of u(Δv, Δω) [R/t0]
  double rms_surface_speed = 0.0;  ///< √(mean over the spheres of u(v, ω)²) after the sweep [R/t0]
  double piston_change = 0.0;      ///< |ΔV_P| [R/t0]
};

/// Compares the velocities after a sweep with those it started from. The snapshot a sweep
/// is measured against is taken in the same pass that measures the sweep before it, so a
/// sweep costs one pass over the spheres; only a change of the velocities between sweeps
/// (the mixing) needs a fresh copy. Buffers are kept from sweep to sweep and step to step
/// (no allocation in steady state).
class KinematicChange {
 public:
  /// Remembers v*, ω*, V_P* before the first sweep of a step, and R² of every sphere from
  /// the cache's Δt/m and Δt/I (solid sphere: I = 0.4 m R²).
  void begin_step(const VelocityCache& velocities);

  /// Remembers the velocities again after something other than a sweep changed them (the
  /// mixing), so the next sweep is measured from them.
  void velocities_changed(const VelocityCache& velocities);

  /// The change since the last snapshot, which then moves to the velocities now. The RMS
  /// speed is summed only when `with_speed` (the rule reads it once its window is full);
  /// otherwise it is 0.
  [[nodiscard]] SweepMotion after_sweep(const VelocityCache& velocities, bool with_speed);

  /// Spheres side by side: a block holds four, field by field (lane l = sphere 4b + l), so
  /// the pass runs 2 (SSE2) or 4 (AVX2) lanes at a time (lanes.hpp).
  static constexpr std::size_t kBlock = 4;

  /// Blocks that hold `spheres` spheres.
  static constexpr std::size_t blocks_of(std::size_t spheres) {
    return (spheres + kBlock - 1) / kBlock;
  }

  /// The snapshot of spheres 4b .. 4b + 3 (zeros past the last sphere).
  struct alignas(32) Block {
    std::array<std::array<double, kBlock>, 3> linear;
    std::array<std::array<double, kBlock>, 3> angular;
  };

 private:
  std::vector<Block> start_;
  AlignedVector<double> radius_sq_;  ///< R² per sphere, zeros to a whole block
  double piston_start_ = 0.0;
};

}  // namespace cdpowder
