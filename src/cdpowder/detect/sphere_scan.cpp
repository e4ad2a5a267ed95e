// sphere_scan.cpp — the passes over the spheres in lanes (sphere_scan_lanes.inc, compiled for
// SSE2 and for AVX2), the last partial block sphere by sphere with the same expressions.
#include "cdpowder/detect/sphere_scan.hpp"

#include "cdpowder/core/lanes.hpp"

#include <algorithm>

namespace cdpowder {

#define CDP_LANE_CODE "cdpowder/detect/sphere_scan_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

double largest_surface_speed(const Bodies& bodies, std::size_t first, std::size_t last) {
  double v_max = 0.0;
  const std::size_t rest = CDP_LANES_FOR_CPU(surface_speed_lanes)(bodies, first, last, v_max);
  for (std::size_t i = rest; i < last; ++i) {
    const double surface_speed =
        bodies.velocity[i].norm() + bodies.radius[i] * bodies.angular_velocity[i].norm();
    v_max = std::max(v_max, surface_speed);
  }
  return v_max;
}

bool all_within(const Vec3* position, const Vec3* anchor, const PeriodicBox& box, double slack_sq,
                std::size_t first, std::size_t last) {
  std::size_t rest = first;
  if (!CDP_LANES_FOR_CPU(within_lanes)(position, anchor, box, slack_sq, first, last, rest)) {
    return false;
  }
  for (std::size_t i = rest; i < last; ++i) {
    if (box.minimum_image(position[i] - anchor[i]).squaredNorm() > slack_sq) return false;
  }
  return true;
}

}  // namespace cdpowder
