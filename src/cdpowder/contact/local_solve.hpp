// local_solve.hpp — the single-contact problem with six relative modes, solved in one
// block Gauss–Seidel pass per visit (physics.md §5.3–5.5):
//   1 normal   shifted Signorini with cohesion on g_pos (UK03 eq. 33–34, §5.4 step 1)
//   2 sliding  |R_t| ≤ μ S                (Bartels et al. eq. Ftmax_coh)
//   3 rolling  |T_t| ≤ μ_t S r_eff        (Bartels et al. eq. max_torques)
//   4 torsion  |T_n| ≤ μ_n S r_eff
// with S = R_n + F_c. Each mode's trial value is its stored value minus its own
// relative velocity divided by its diagonal Δt w of W, e.g.
//   R_n,trial = R_n,old − (V_n + g_pos/Δt) / (Δt w_n),
// which is −(g_pos/Δt + U_n)/(Δt w_n) of §5.4 with U_n = V_n − Δt w_n R_n,old.
// The change of each mode is pushed into the velocity cache at once, so the next mode
// (and the next contact) sees it. For equal spheres (c = 0 in §5.2) one pass is the
// exact local solution; at walls and for unequal spheres sliding and rolling couple and
// the global iteration converges the pair.
#pragma once

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/contact/velocity_change.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

/// What one visit changed, for the stopping rules (torques divided by r_eff). Squares, so
/// the kernel takes no square root unless a threshold clamps.
struct VisitChange {
  double change_sq = 0.0;  ///< max(ΔR_n², |ΔR_t|², |ΔT_t|²/r_eff², ΔT_n²/r_eff²) [F_coh²]
};

/// A mode has a threshold above zero (μ_t r_eff or μ_n r_eff > 0); without one its torque
/// is zero, and the kernel and the mixing skip it (nlgs.cpp).
inline bool has_threshold(double cap) {
  return cap > 0.0;
}

namespace detail {

/// 1/r_eff², turning squared torques into squared forces for the residuals.
inline double torque_scale_sq(double r_eff) {
  return r_eff > 0.0 ? 1.0 / (r_eff * r_eff) : 1.0;
}

/// Squared size of an action change (torques scaled by 1/r_eff²), for the residuals.
inline double action_size_sq(double R_n, const Vec3& R_t, const Vec3& T_t, double T_n,
                             double inv_r_sq) {
  return std::max(
      {R_n * R_n, R_t.squaredNorm(), T_t.squaredNorm() * inv_r_sq, T_n * T_n * inv_r_sq});
}

/// Constants of one visit that differ between the pair and the wall kernel.
struct ModeBlock {
  double inv_dt_w_n, inv_dt_w_t, inv_dt_w_r;  ///< 1/(Δt w) of the three blocks (§5.2)
  double cohesion, mu, roll_cap, twist_cap;   ///< F_c, μ, μ_t r_eff, μ_n r_eff
  double gap_rate;                            ///< g_pos/Δt
  double coupling;  ///< Δt c: a sliding change ΔR_t moves Ω by Δt c (n × ΔR_t) (§5.2)
  double inv_r_sq;  ///< 1/r_eff² for the residual
};

/// The four modes of §5.4 for relative velocities V, Ω of the contact points. Writes the
/// new action and returns the change (ΔR, ΔT) to apply to the bodies, so each body is
/// updated once per visit. The normal change moves neither V_t nor Ω, and the sliding
/// change moves Ω only through the coupling, so the modes can be solved on local copies.
[[gnu::always_inline]] inline VisitChange solve_modes(const Vec3& n, const Vec3& V,
                                                      const Vec3& Omega, const ModeBlock& m,
                                                      ContactAction& action, Vec3& dR, Vec3& dT) {
  VisitChange out;
  const double V_n = V.dot(n);
  // 1 normal: closed iff the trial force keeps S = R_n + F_c ≥ 0
  const double R_n_trial = action.normal_force - m.inv_dt_w_n * (V_n + m.gap_rate);
  if (R_n_trial < -m.cohesion) {
    // open or opening: R_n = −F_c, every threshold is zero (§5.4 step 1)
    const double dR_n = -m.cohesion - action.normal_force;
    dR = dR_n * n - action.tangential_force;
    dT = -action.rolling_torque - action.twisting_torque * n;
    out.change_sq = action_size_sq(dR_n, action.tangential_force, action.rolling_torque,
                                   action.twisting_torque, m.inv_r_sq);
    action = ContactAction{};
    action.normal_force = -m.cohesion;
    return out;
  }
  const double dR_n = R_n_trial - action.normal_force;
  action.normal_force = R_n_trial;
  const double S = R_n_trial + m.cohesion;

  // 2 sliding: stick if the trial force is inside the disc μ S, else slide on its rim
  const Vec3 V_t = V - V_n * n;
  const Vec3 R_t = clamp_to_disc(action.tangential_force - m.inv_dt_w_t * V_t, m.mu * S);
  const Vec3 dR_t = R_t - action.tangential_force;
  action.tangential_force = R_t;

  // 3 rolling and 4 torsion, from Ω after the sliding change (it moves Ω_t if c ≠ 0).
  // A mode without friction (μ_t = 0: the paper's (0, μn) axis and the (0,0) corner; μ_n = 0)
  // carries no torque: +0, without the square root and division of its clamp (a fifth of the
  // kernel's time at (0,0)); with neither, Ω after the sliding change is not needed at all.
  Vec3 T_t = Vec3::Zero();
  double T_n = 0.0;
  if (has_threshold(m.roll_cap) || has_threshold(m.twist_cap)) {
    const Vec3 Omega_1 = Omega + m.coupling * n.cross(dR_t);
    const double Omega_n = Omega_1.dot(n);
    const Vec3 Omega_t = Omega_1 - Omega_n * n;
    if (has_threshold(m.roll_cap)) {
      T_t = clamp_to_disc(action.rolling_torque - m.inv_dt_w_r * Omega_t, m.roll_cap * S);
    }
    if (has_threshold(m.twist_cap)) {
      T_n = clamp_to_interval(action.twisting_torque - m.inv_dt_w_r * Omega_n, m.twist_cap * S);
    }
  }
  const Vec3 dT_t = T_t - action.rolling_torque;
  const double dT_n = T_n - action.twisting_torque;
  action.rolling_torque = T_t;
  action.twisting_torque = T_n;

  dR = dR_n * n + dR_t;
  dT = dT_t + dT_n * n;
  out.change_sq = action_size_sq(dR_n, dR_t, dT_t, dT_n, m.inv_r_sq);
  return out;
}

}  // namespace detail

/// Relative velocities of a pair's contact points: V = v_b + ω_b×l_b − v_a − ω_a×l_a (§5.1)
/// and Ω = ω_b − ω_a.
inline void pair_relative_velocity(const PairProblem& p, const SphereVelocity& a,
                                   const SphereVelocity& b, Vec3& V, Vec3& Omega) {
  V = (b.linear - a.linear) - (p.lever_a * a.angular + p.lever_b * b.angular).cross(p.normal);
  Omega = b.angular - a.angular;
}

inline detail::ModeBlock pair_mode_block(const PairProblem& p, const SphereVelocity& a,
                                         const SphereVelocity& b) {
  return detail::ModeBlock{p.inv_dt_w_n,
                           p.inv_dt_w_t,
                           p.inv_dt_w_r,
                           p.cohesion,
                           p.mu,
                           p.roll_cap,
                           p.twist_cap,
                           p.gap_rate,
                           p.lever_a * a.dt_inverse_inertia - p.lever_b * b.dt_inverse_inertia,
                           detail::torque_scale_sq(p.r_eff)};
}

/// One visit of a sphere–sphere contact.
inline VisitChange solve_pair(const PairProblem& p, ContactAction& action, SphereVelocity& a,
                              SphereVelocity& b) {
  Vec3 V;
  Vec3 Omega;
  pair_relative_velocity(p, a, b, V, Omega);
  Vec3 dR;
  Vec3 dT;
  const VisitChange out =
      detail::solve_modes(p.normal, V, Omega, pair_mode_block(p, a, b), action, dR, dT);
  apply_pair_delta(p, dR, dT, a, b);
  return out;
}

/// Two visits of pair contacts that share no sphere, written side by side so that their
/// independent dependency chains overlap: the same arithmetic, and the same result, as
/// solve_pair(p, …) followed by solve_pair(q, …).
inline void solve_two_pairs(const PairProblem& p, ContactAction& x, SphereVelocity& a,
                            SphereVelocity& b, VisitChange& out_p, const PairProblem& q,
                            ContactAction& y, SphereVelocity& c, SphereVelocity& d,
                            VisitChange& out_q) {
  Vec3 V_p;
  Vec3 Omega_p;
  Vec3 V_q;
  Vec3 Omega_q;
  pair_relative_velocity(p, a, b, V_p, Omega_p);
  pair_relative_velocity(q, c, d, V_q, Omega_q);
  Vec3 dR_p;
  Vec3 dT_p;
  Vec3 dR_q;
  Vec3 dT_q;
  out_p = detail::solve_modes(p.normal, V_p, Omega_p, pair_mode_block(p, a, b), x, dR_p, dT_p);
  out_q = detail::solve_modes(q.normal, V_q, Omega_q, pair_mode_block(q, c, d), y, dR_q, dT_q);
  apply_pair_delta(p, dR_p, dT_p, a, b);
  apply_pair_delta(q, dR_q, dT_q, c, d);
}

/// One visit of a sphere–wall contact (wall = body a, sphere = body b, lever −R n):
/// V = v_s − R ω_s × n − V_wall e_z, Ω = ω_s. `wall_velocity` is V_P*; only piston contacts
/// read or write it (the bottom wall is immobile, V_wall = +0).
inline VisitChange solve_wall(const WallProblem& w, ContactAction& action, SphereVelocity& s,
                              double& wall_velocity) {
  const Vec3& n = w.normal;
  const double wall_z = w.wall_moves != 0.0 ? w.wall_moves * wall_velocity : 0.0;
  // V = v_s − R ω_s × n − (0, 0, V_wall), written out with Eigen's cross product operation for
  // operation (x − (+0) leaves x's bits). In vector form g++ packed two of its components
  // through the stack, and the wide load of two narrow stores stalled every visit.
  const Vec3& omega = s.angular;
  const double cross_x = omega.y() * n.z() - omega.z() * n.y();
  const double cross_y = omega.z() * n.x() - omega.x() * n.z();
  const double cross_z = omega.x() * n.y() - omega.y() * n.x();
  const Vec3 V(s.linear.x() - w.radius * cross_x, s.linear.y() - w.radius * cross_y,
               (s.linear.z() - w.radius * cross_z) - wall_z);
  const detail::ModeBlock m{w.inv_dt_w_n,
                            w.inv_dt_w_t,
                            w.inv_dt_w_r,
                            w.cohesion,
                            w.mu,
                            w.roll_cap,
                            w.twist_cap,
                            w.gap_rate,
                            -w.radius * s.dt_inverse_inertia,
                            detail::torque_scale_sq(w.radius)};
  Vec3 dR;
  Vec3 dT;
  const VisitChange out = detail::solve_modes(n, V, s.angular, m, action, dR, dT);
  apply_wall_delta(w, dR, dT, s, wall_velocity);
  return out;
}

}  // namespace cdpowder
