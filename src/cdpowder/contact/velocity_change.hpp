// velocity_change.hpp — the velocity-cache kinematics of a contact (physics.md §5.5
// "apply Δ"): how a change (ΔR, ΔT) of a contact's action moves v*, ω* of its bodies. The
// kernels (local_solve.hpp, the lane kernels of solver/nlgs/), the warm start
// (solver/build.cpp) and the mixing all move the cache through these.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/vec3.hpp"

namespace cdpowder {

/// The force ΔR = R_n n + R_t and the couple ΔT = T_t + T_n n of an action (or of a change
/// of one) on a contact of normal n: what the functions below move the bodies by.
inline Vec3 action_force(const ContactAction& action, const Vec3& normal) {
  return action.normal_force * normal + action.tangential_force;
}

inline Vec3 action_torque(const ContactAction& action, const Vec3& normal) {
  return action.rolling_torque + action.twisting_torque * normal;
}

/// Velocity change of sphere a alone, and of sphere b alone, from a change (ΔR, ΔT) of the
/// action on b (§5.5): Δv_b = Δt ΔR/m_b, Δω_b = Δt (l_b × ΔR + ΔT)/I_b, and the opposite on a
/// (levers of PairProblem: to the common contact point), given n × ΔR
/// (l_a × ΔR = |l_a| n×ΔR, l_b × ΔR = −|l_b| n×ΔR). A caller that updates the two spheres on
/// different threads calls one each (solver/build.cpp).
inline void apply_pair_delta_to_a(const PairProblem& p, const Vec3& dR, const Vec3& dT,
                                  const Vec3& n_cross_dR, SphereVelocity& a) {
  a.linear -= a.dt_inverse_mass * dR;
  a.angular -= a.dt_inverse_inertia * (p.lever_a * n_cross_dR + dT);
}

inline void apply_pair_delta_to_b(const PairProblem& p, const Vec3& dR, const Vec3& dT,
                                  const Vec3& n_cross_dR, SphereVelocity& b) {
  b.linear += b.dt_inverse_mass * dR;
  b.angular += b.dt_inverse_inertia * (dT - p.lever_b * n_cross_dR);
}

/// Velocity change of both spheres from a change (ΔR, ΔT) of the action on b.
inline void apply_pair_delta(const PairProblem& p, const Vec3& dR, const Vec3& dT,
                             SphereVelocity& a, SphereVelocity& b) {
  const Vec3 n_cross_dR = p.normal.cross(dR);
  apply_pair_delta_to_a(p, dR, dT, n_cross_dR, a);
  apply_pair_delta_to_b(p, dR, dT, n_cross_dR, b);
}

/// Velocity change of a sphere (body b, lever −R n) alone, and of the wall (body a: only the
/// piston moves, along z) alone, from a change (ΔR, ΔT) of the action on the sphere. A
/// bottom-wall contact leaves V_P alone (not even adding 0): it neither reads (solve_wall) nor
/// writes V_P, so it may be solved on another thread than the piston's contacts
/// (solver/nlgs/tiles.hpp: a tile's bottom-wall contacts, the hub's piston contacts).
inline void apply_wall_delta_to_sphere(const WallProblem& w, const Vec3& dR, const Vec3& dT,
                                       SphereVelocity& s) {
  s.linear += s.dt_inverse_mass * dR;
  s.angular += s.dt_inverse_inertia * (dT - w.radius * w.normal.cross(dR));
}

inline void apply_wall_delta_to_wall(const WallProblem& w, const Vec3& dR, double& wall_velocity) {
  if (w.wall_moves != 0.0) wall_velocity -= w.wall_response * dR.z();
}

/// Velocity change of the sphere and of the wall.
inline void apply_wall_delta(const WallProblem& w, const Vec3& dR, const Vec3& dT,
                             SphereVelocity& s, double& wall_velocity) {
  apply_wall_delta_to_sphere(w, dR, dT, s);
  apply_wall_delta_to_wall(w, dR, wall_velocity);
}

/// Adds the velocity change that a whole action on a contact causes to both of its bodies:
/// ΔR = R_n n + R_t, ΔT = T_t + T_n n. Used for the warm start and by the mixing.
void apply_pair_action(const PairProblem& p, const ContactAction& delta, VelocityCache& v);
void apply_wall_action(const WallProblem& w, const ContactAction& delta, VelocityCache& v);
/// apply_wall_action with the wall's velocity change added to `wall_velocity` (a tiled
/// step's mixing keeps each tile's change of the piston apart: tile_solve.hpp).
void apply_wall_action(const WallProblem& w, const ContactAction& delta, SphereVelocity& s,
                       double& wall_velocity);

}  // namespace cdpowder
