// kinematic_change.cpp — one pass over the spheres after a sweep.
#include "cdpowder/solver/kinematic_change.hpp"

#include <algorithm>
#include <cstddef>

namespace cdpowder {

void KinematicChange::before_sweep(const VelocityCache& velocities, bool new_step) {
  start_.assign(velocities.spheres.begin(), velocities.spheres.end());
  piston_start_ = velocities.piston_velocity;
  if (!new_step && radius_sq_.size() == start_.size()) return;
  radius_sq_.resize(start_.size());
  for (std::size_t i = 0; i < start_.size(); ++i) {
    // I/m = (Δt/m)/(Δt/I) = 0.4 R²; a fixed sphere (Δt/I = 0) does not turn
    const SphereVelocity& s = start_[i];
    radius_sq_[i] =
        s.dt_inverse_inertia > 0.0 ? 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia : 0.0;
  }
}

SweepMotion KinematicChange::after_sweep(const VelocityCache& velocities) const {
  double largest_sq = 0.0;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < start_.size(); ++i) {
    const SphereVelocity& now = velocities.spheres[i];
    const double r_sq = radius_sq_[i];
    largest_sq = std::max(largest_sq, (now.linear - start_[i].linear).squaredNorm() +
                                          r_sq * (now.angular - start_[i].angular).squaredNorm());
    sum_sq += now.linear.squaredNorm() + r_sq * now.angular.squaredNorm();
  }
  SweepMotion motion;
  motion.largest_change = std::sqrt(largest_sq);
  motion.rms_surface_speed =
      start_.empty() ? 0.0 : std::sqrt(sum_sq / static_cast<double>(start_.size()));
  motion.piston_change = std::abs(velocities.piston_velocity - piston_start_);
  return motion;
}

}  // namespace cdpowder
