// deposition_config.hpp — the [deposition] table of a scene: how many spheres of which radii
// are deposited into which cell, and how the capture radius r_capt is read (physics.md §8.1,
// §16). The deposit itself is setup/deposition.hpp's.
#pragma once

#include <cstdint>

namespace cdpowder {

/// How r_capt is read (physics.md §8.1, §16).
enum class CaptureRule {
  /// r_capt is the centre-to-centre distance of two reference spheres: a falling sphere is
  /// captured when its surface gap falls below r_capt − 2 R_ref (default; r_capt = 2R is
  /// plain ballistic deposition). R_ref is the mean radius.
  CentreDistance,
  SurfaceGap,  ///< r_capt is the surface gap itself
};

struct DepositionConfig {
  int spheres = 1015;           ///< N (paper: 1015)
  double lx = 25.0;             ///< L_x [R] (paper: 25)
  double ly = 25.0;             ///< L_y [R]
  double radius_min = 1.0;      ///< radii are uniform in [radius_min, radius_max] [R]
  double radius_max = 1.0;      ///< equal to radius_min: monodisperse (the paper)
  double capture_radius = 3.0;  ///< r_capt [R] (paper: 3)
  CaptureRule capture_rule = CaptureRule::CentreDistance;
  std::uint64_t seed = 1;  ///< seed of the deposition stream

  /// Surface gap below which a falling sphere is captured [R].
  [[nodiscard]] double capture_gap() const {
    return capture_rule == CaptureRule::SurfaceGap ? capture_radius
                                                   : capture_radius - (radius_min + radius_max);
  }
};

}  // namespace cdpowder
