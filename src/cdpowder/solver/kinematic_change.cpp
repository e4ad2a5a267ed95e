// kinematic_change.cpp — one pass over the spheres after a sweep.
#include "cdpowder/solver/kinematic_change.hpp"

#include <algorithm>
#include <array>
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

namespace {

using Lanes = KinematicChange::Lanes;

/// Lane l of each field from sphere 2b + l; a missing second sphere (odd count) reads zeros.
struct SpherePair {
  const SphereVelocity& first;
  const SphereVelocity& second;

  [[nodiscard]] Lanes linear(int k) const { return Lanes{first.linear[k], second.linear[k]}; }

  [[nodiscard]] Lanes angular(int k) const { return Lanes{first.angular[k], second.angular[k]}; }
};

const SphereVelocity kNoSphere{};

SpherePair pair_at(const std::vector<SphereVelocity>& spheres, std::size_t b) {
  const std::size_t i = 2 * b;
  return {spheres[i], i + 1 < spheres.size() ? spheres[i + 1] : kNoSphere};
}

/// |a|² lane by lane as Eigen's squaredNorm sums it: (x² + y²) + z²
inline Lanes norm_sq(Lanes x, Lanes y, Lanes z) {
  return (x * x + y * y) + z * z;
}

}  // namespace

void KinematicChange::velocities_changed(const VelocityCache& velocities) {
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  start_.resize((spheres.size() + 1) / 2);
  for (std::size_t b = 0; b < start_.size(); ++b) {
    const SpherePair now = pair_at(spheres, b);
    for (int k = 0; k < 3; ++k) {
      start_[b].linear[k] = now.linear(k);
      start_[b].angular[k] = now.angular(k);
    }
  }
  piston_start_ = velocities.piston_velocity;
}

namespace {

/// One pass, two spheres side by side: the largest u(Δv, Δω)², the snapshot moved to now,
/// and (kWithSpeed) Σ u(v, ω)². Each sphere's value is formed with the operations of one
/// sphere at a time, the maximum does not depend on the order, and the sum adds the spheres
/// one by one in index order: the same bits as a loop over the spheres.
template <bool kWithSpeed>
void measure(const std::vector<SphereVelocity>& spheres, std::vector<KinematicChange::Block>& start,
             const std::vector<double>& radius_sq, double& largest_sq, double& sum_sq) {
  const std::size_t n = spheres.size();
  for (std::size_t b = 0; b < start.size(); ++b) {
    const SpherePair now = pair_at(spheres, b);
    KinematicChange::Block& was = start[b];
    const Lanes r_sq{radius_sq[2 * b], 2 * b + 1 < n ? radius_sq[2 * b + 1] : 0.0};
    const std::array<Lanes, 3> v = {now.linear(0), now.linear(1), now.linear(2)};
    const std::array<Lanes, 3> w = {now.angular(0), now.angular(1), now.angular(2)};
    const Lanes change =
        norm_sq(v[0] - was.linear[0], v[1] - was.linear[1], v[2] - was.linear[2]) +
        r_sq * norm_sq(w[0] - was.angular[0], w[1] - was.angular[1], w[2] - was.angular[2]);
    largest_sq = std::max(largest_sq, change[0]);
    largest_sq = std::max(largest_sq, change[1]);  // 0 for a missing second sphere
    was.linear = v;
    was.angular = w;
    if constexpr (kWithSpeed) {
      const Lanes speed_sq = norm_sq(v[0], v[1], v[2]) + r_sq * norm_sq(w[0], w[1], w[2]);
      sum_sq += speed_sq[0];
      if (2 * b + 1 < n) sum_sq += speed_sq[1];
    }
  }
}

}  // namespace

SweepMotion KinematicChange::after_sweep(const VelocityCache& velocities, bool with_speed) {
  double largest_sq = 0.0;
  double sum_sq = 0.0;
  const std::size_t n = velocities.spheres.size();
  if (with_speed) {
    measure<true>(velocities.spheres, start_, radius_sq_, largest_sq, sum_sq);
  } else {
    measure<false>(velocities.spheres, start_, radius_sq_, largest_sq, sum_sq);
  }
  SweepMotion motion;
  motion.largest_change = std::sqrt(largest_sq);
  motion.rms_surface_speed = n == 0 ? 0.0 : std::sqrt(sum_sq / static_cast<double>(n));
  motion.piston_change = std::abs(velocities.piston_velocity - piston_start_);
  piston_start_ = velocities.piston_velocity;
  return motion;
}

}  // namespace cdpowder
