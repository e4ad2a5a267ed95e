// contact_law.hpp — parameters of the contact laws (Bartels et al. §2) and the
// projections each mode uses (physics.md §5.4).
//   sliding   |R_t| ≤ μ   (F_n + F_coh)            (paper eq. Ftmax_coh)
//   rolling   |T_t| ≤ μ_t (F_n + F_coh) r_eff       (paper eq. max_torques)
//   torsion   |T_n| ≤ μ_n (F_n + F_coh) r_eff
// The thresholds use S = F_n + F_coh, never max(F_n, 0): a closed, unloaded cohesive
// contact still resists with μ F_coh, μ_t F_coh r_eff, μ_n F_coh r_eff.
#pragma once

#include "cdpowder/core/vec3.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

/// Coefficients of one family of contacts (sphere–sphere, or sphere–wall).
struct ContactLaw {
  double mu = 0.3;               ///< μ, sliding friction coefficient [-]
  double mu_roll = 0.0;          ///< μ_t, rolling friction coefficient [-]
  double mu_twist = 0.0;         ///< μ_n, torsion friction coefficient [-]
  double cohesion_force = 1.0;   ///< F_coh, constant attraction of a cohesive contact [F_coh]
  double cohesion_range = 0.01;  ///< d_coh, gap up to which the attraction acts [R] (§6.3)
};

/// Which pairs are cohesion-active in a step (physics.md §6.2).
enum class CohesionRule {
  Graph,    ///< active iff the start-of-step gap g ≤ d_coh
  History,  ///< active iff g ≤ 1e-6 R (touching, solver/build.cpp), or active in the previous step
            ///< and g ≤ d_coh
};

/// All laws of a scene.
struct ContactLaws {
  ContactLaw spheres;              ///< between two spheres
  ContactLaw walls;                ///< sphere–bottom wall and sphere–piston
  double wall_r_eff_factor = 1.0;  ///< r_eff at a wall = factor × R_sphere (R_wall → ∞ limit)
  CohesionRule cohesion_rule = CohesionRule::Graph;
};

/// r_eff = (1/R_1 + 1/R_2)^-1, the lever of the torque thresholds [R].
inline double effective_radius(double radius_a, double radius_b) {
  return radius_a * radius_b / (radius_a + radius_b);
}

/// Projects a tangential trial vector onto the disc of radius `limit` keeping its
/// direction. Exact for the isotropic sliding and rolling blocks (physics.md §5.4).
inline Vec3 clamp_to_disc(const Vec3& trial, double limit) {
  const double norm_squared = trial.squaredNorm();
  if (norm_squared <= limit * limit) return trial;
  return trial * (limit / std::sqrt(norm_squared));
}

/// Projects a scalar trial value onto [-limit, limit] (torsion, physics.md §5.4 step 4).
inline double clamp_to_interval(double trial, double limit) {
  return std::clamp(trial, -limit, limit);
}

}  // namespace cdpowder
