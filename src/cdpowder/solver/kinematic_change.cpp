// kinematic_change.cpp — one pass over the spheres after a sweep.
#include "cdpowder/solver/kinematic_change.hpp"

#include <algorithm>
#include <cstddef>

namespace cdpowder {

void KinematicChange::begin_step(const VelocityCache& velocities) {
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  radius_sq_.resize(spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    // I/m = (Δt/m)/(Δt/I) = 0.4 R²; a fixed sphere (Δt/I = 0) does not turn
    const SphereVelocity& s = spheres[i];
    radius_sq_[i] =
        s.dt_inverse_inertia > 0.0 ? 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia : 0.0;
  }
  velocities_changed(velocities);
}

void KinematicChange::velocities_changed(const VelocityCache& velocities) {
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  start_.resize(2 * spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    start_[2 * i] = spheres[i].linear;
    start_[2 * i + 1] = spheres[i].angular;
  }
  piston_start_ = velocities.piston_velocity;
}

namespace {

/// |a|² as Eigen's squaredNorm sums it: (x² + y²) + z²
inline double norm_sq(double x, double y, double z) {
  return (x * x + y * y) + z * z;
}

/// One pass: the largest u(Δv, Δω)², the snapshot moved to now, and (kWithSpeed) Σ u(v, ω)².
template <bool kWithSpeed>
void measure(const SphereVelocity* now, Vec3* start, const double* radius_sq, std::size_t n,
             double& largest_sq, double& sum_sq) {
  for (std::size_t i = 0; i < n; ++i) {
    const double* v = now[i].linear.data();
    const double* w = now[i].angular.data();
    double* s = start[2 * i].data();      // linear
    double* t = start[2 * i + 1].data();  // angular
    const double change = norm_sq(v[0] - s[0], v[1] - s[1], v[2] - s[2]) +
                          radius_sq[i] * norm_sq(w[0] - t[0], w[1] - t[1], w[2] - t[2]);
    largest_sq = std::max(largest_sq, change);
    for (int k = 0; k < 3; ++k) {
      s[k] = v[k];
      t[k] = w[k];
    }
    if constexpr (kWithSpeed) {
      sum_sq += norm_sq(v[0], v[1], v[2]) + radius_sq[i] * norm_sq(w[0], w[1], w[2]);
    }
  }
}

}  // namespace

SweepMotion KinematicChange::after_sweep(const VelocityCache& velocities, bool with_speed) {
  double largest_sq = 0.0;
  double sum_sq = 0.0;
  const std::size_t n = radius_sq_.size();
  if (with_speed) {
    measure<true>(velocities.spheres.data(), start_.data(), radius_sq_.data(), n, largest_sq,
                  sum_sq);
  } else {
    measure<false>(velocities.spheres.data(), start_.data(), radius_sq_.data(), n, largest_sq,
                   sum_sq);
  }
  SweepMotion motion;
  motion.largest_change = std::sqrt(largest_sq);
  motion.rms_surface_speed = n == 0 ? 0.0 : std::sqrt(sum_sq / static_cast<double>(n));
  motion.piston_change = std::abs(velocities.piston_velocity - piston_start_);
  piston_start_ = velocities.piston_velocity;
  return motion;
}

}  // namespace cdpowder
