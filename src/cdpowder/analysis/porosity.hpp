// porosity.hpp — E = (V − V_grains)/V (Bartels et al. eq. porosity, physics.md §11.1).
#pragma once

#include "cdpowder/model/world.hpp"

namespace cdpowder {

/// Σ (4/3) π R_i³ over all spheres [R³].
double grain_volume(const Bodies& bodies);

/// Volume of the packing [R³]: L_x L_y Z_P between the bottom (z = 0) and the piston face;
/// without a piston, L_x L_y (max_i (z_i + R_i)).
double packing_volume(const World& world);

/// Porosity E = 1 − V_grains / V [-].
double porosity(const World& world);

}  // namespace cdpowder
