// walls.hpp — the two planar boundaries of the experiment (physics.md §4.1, §9):
// an immobile bottom wall at z = 0 and a piston, a horizontal rigid plate that
// translates along z only and is pushed down by a constant force.
#pragma once

namespace cdpowder {

struct BottomWall {
  bool enabled = false;  ///< the plane z = 0 exists
};

struct Piston {
  bool enabled = false;
  double height = 0.0;    ///< Z_P, z of the piston's lower face [R]
  double velocity = 0.0;  ///< V_P, along z (negative = moving down) [R/t0]
  double mass = 1000.0;   ///< M_P [ρR³]; the paper's value (Bartels et al. §3)
  double force = 0.0;     ///< F ≥ 0, constant push along −z [F_coh]

  [[nodiscard]] double inverse_mass() const { return mass > 0.0 ? 1.0 / mass : 0.0; }
};

struct Walls {
  BottomWall bottom;
  Piston piston;
};

}  // namespace cdpowder
