// kinematic_change.cpp — one pass over the spheres after a sweep, in lanes
// (kinematic_lanes.inc, compiled for SSE2 and for AVX2 like the coloured kernel).
#include "cdpowder/solver/kinematic_change.hpp"

#include "cdpowder/solver/lanes.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace cdpowder {

#define CDP_LANE_CODE "cdpowder/solver/kinematic_lanes.inc"
#include "cdpowder/solver/lanes_instantiate.inc"

void KinematicChange::begin_step(const VelocityCache& velocities) {
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  radius_sq_.assign(blocks_of(spheres.size()) * kBlock, 0.0);
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    // I/m = (Δt/m)/(Δt/I) = 0.4 R²; a fixed sphere (Δt/I = 0) does not turn
    const SphereVelocity& s = spheres[i];
    radius_sq_[i] =
        s.dt_inverse_inertia > 0.0 ? 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia : 0.0;
  }
  velocities_changed(velocities);
}

void KinematicChange::velocities_changed(const VelocityCache& velocities) {
  const std::size_t n = velocities.spheres.size();
  start_.resize(blocks_of(n));
  CDP_LANES_FOR_CPU(copy_into)(velocities.spheres.data(), n, start_.data());
  piston_start_ = velocities.piston_velocity;
}

SweepMotion KinematicChange::after_sweep(const VelocityCache& velocities, bool with_speed) {
  double largest_sq = 0.0;
  double sum_sq = 0.0;
  const std::size_t n = velocities.spheres.size();
  const auto measure =
      with_speed ? CDP_LANES_FOR_CPU(measure<true>) : CDP_LANES_FOR_CPU(measure<false>);
  measure(velocities.spheres.data(), n, start_.data(), radius_sq_.data(), largest_sq, sum_sq);
  SweepMotion motion;
  motion.largest_change = std::sqrt(largest_sq);
  motion.rms_surface_speed = n == 0 ? 0.0 : std::sqrt(sum_sq / static_cast<double>(n));
  motion.piston_change = std::abs(velocities.piston_velocity - piston_start_);
  piston_start_ = velocities.piston_velocity;
  return motion;
}

}  // namespace cdpowder
