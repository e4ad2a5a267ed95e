// deposition.hpp — ballistic deposition with a capture radius (Bartels et al. §3;
// physics.md §8): spheres fall vertically one by one at random (x, y) and stick for good
// as soon as they come closer than the capture distance to the deposit or the substrate.
// The result is a very loose, tree-like deposit, periodic in x and y.
#pragma once

#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"

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

/// Appends config.spheres deposited spheres (at rest, density `density`) to `bodies`, which
/// must be empty. Every sphere touches the substrate (z = R) or a sphere deposited before
/// it; none overlaps another (up to round-off). `stop_requested` is asked every 256
/// spheres (a 60 000-sphere deposit takes ≈ 10 s); when it answers true, throws Interrupted
/// (and `bodies` holds the spheres deposited so far).
void deposit_ballistically(const DepositionConfig& config, double density, Bodies& bodies,
                           const StopRequest& stop_requested = {});

/// Height of a deposit: max_i (z_i + R_i), 0 when empty [R].
double deposit_height(const Bodies& bodies);

/// Porosity of a deposit: 1 − V_grains / (L_x L_y (max_i z_i + R_i)) (physics.md §8.2).
double deposit_porosity(const Bodies& bodies, const PeriodicBox& box);

}  // namespace cdpowder
