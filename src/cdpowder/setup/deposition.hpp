// deposition.hpp — ballistic deposition with a capture radius (Bartels et al. §3;
// physics.md §8): spheres fall vertically one by one at random (x, y) and stick for good
// as soon as they come closer than the capture distance to the deposit or the substrate.
// The result is a very loose, tree-like deposit, periodic in x and y.
#pragma once

#include "cdpowder/config/deposition_config.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"

namespace cdpowder {

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
