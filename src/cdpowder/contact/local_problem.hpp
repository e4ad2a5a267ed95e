// local_problem.hpp — one step's contact set: the frozen geometry and inverse-mass
// terms of every contact (physics.md §4.2, §5.2), and its unknowns.
// Built once per step by build_local_problems, read-only during the passes.
// Sphere–sphere and sphere–wall contacts live in separate arrays, so each kernel is
// branch-free; the pass visits a combined index range (pairs first, then walls).
#pragma once

#include "cdpowder/core/index.hpp"
#include "cdpowder/core/vec3.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

/// Unknowns of one contact: the action on body b (the reaction acts on a).
/// Force R = R_n n + R_t at the contact point, couple T = T_n n + T_t.
struct ContactAction {
  double normal_force = 0.0;             ///< R_n, positive = repulsive [F_coh]
  Vec3 tangential_force = Vec3::Zero();  ///< R_t ⊥ n, sliding friction [F_coh]
  Vec3 rolling_torque = Vec3::Zero();    ///< T_t ⊥ n [F_coh R]
  double twisting_torque = 0.0;          ///< T_n, torsion torque about n [F_coh R]
};

static_assert(sizeof(ContactAction) == 64, "8 doubles per contact action (a cache line's worth)");

/// Whether a contact with normal force R_n and cohesion F_c (0 if not cohesive) is closed,
/// i.e. carries a force, after its solve: an open or opening contact has R_n = −F_c exactly,
/// a closed one R_n + F_c ≥ 0 (physics.md §5.4, step 1); one exactly at R_n = −F_c carries no
/// excess and counts as open. The one test every count of closed contacts uses.
[[nodiscard]] inline bool is_closed(double normal_force, double cohesion) {
  return normal_force + cohesion > 0.0;
}

/// Sphere a – sphere b. Levers l_a = |l_a| n, l_b = −|l_b| n from each centre to one common
/// contact point, the middle of the gap: |l_a| = R_a + g/2, |l_b| = R_b + g/2 (physics.md
/// §4.2). Equal and opposite forces at one point conserve the pair's angular momentum
/// exactly, also in a step in which a gap g ≠ 0 closes.
struct PairProblem {
  BodyIndex a = 0;
  BodyIndex b = 0;
  Vec3 normal = Vec3::UnitZ();  ///< n, unit, from a to b (minimum image)
  double gap = 0.0;             ///< g = |d| − R_a − R_b at the start of the step [R]
  double gap_rate = 0.0;        ///< g_pos/Δt, g_pos = max(g, 0) (UK03 eq. 33) [R/t0]
  double lever_a = 0.0;         ///< |l_a| = R_a + g/2 [R]
  double lever_b = 0.0;         ///< |l_b| = R_b + g/2 [R]
  double inv_dt_w_n = 0.0;      ///< 1/(Δt w_n), normal block of W (§5.2) [ρR³/t0]
  double inv_dt_w_t = 0.0;      ///< 1/(Δt w_t), sliding block
  double inv_dt_w_r = 0.0;      ///< 1/(Δt w_r), rolling and torsion block [ρR⁵/t0]
  double cohesion = 0.0;        ///< F_c: F_coh if cohesion-active this step, else 0 [F_coh]
  double mu = 0.0;              ///< μ
  double roll_cap = 0.0;        ///< μ_t r_eff [R]
  double twist_cap = 0.0;       ///< μ_n r_eff [R]
  double r_eff = 0.0;           ///< r_eff, scales torques into forces in residuals [R]
};

static_assert(sizeof(PairProblem) == 128, "keep PairProblem at two cache lines");

/// Which wall a WallProblem touches.
enum class WallKind : std::uint32_t { Bottom = 0, Piston = 1 };

/// Wall (body a) – sphere (body b). n points from the wall into the sphere: +e_z at the
/// bottom, −e_z at the piston; the sphere's lever is l_b = −R n.
struct WallProblem {
  BodyIndex sphere = 0;
  WallKind wall = WallKind::Bottom;
  Vec3 normal = Vec3::UnitZ();
  double gap = 0.0;         ///< distance centre–plane minus R [R]
  double gap_rate = 0.0;    ///< g_pos/Δt [R/t0]
  double radius = 0.0;      ///< R of the sphere [R]
  double inv_dt_w_n = 0.0;  ///< includes 1/M_P for the piston
  double inv_dt_w_t = 0.0;
  double inv_dt_w_r = 0.0;
  double cohesion = 0.0;
  double mu = 0.0;
  double roll_cap = 0.0;
  double twist_cap = 0.0;
  double wall_response = 0.0;  ///< Δt/M_P for the piston, 0 for the bottom [t0/(ρR³)]
  double wall_moves = 0.0;     ///< 1 for the piston (its velocity enters V), 0 for the bottom
};

static_assert(sizeof(WallProblem) == 128, "keep WallProblem at two cache lines");

/// The step's contact set. Index k < pairs.size() is a pair, else wall k − pairs.size().
struct Contacts {
  std::vector<PairProblem> pairs;
  std::vector<ContactAction> pair_actions;
  std::vector<std::uint8_t> pair_cohesive;  ///< 1 if F_c > 0 this step
  std::vector<WallProblem> walls;
  std::vector<ContactAction> wall_actions;
  std::vector<std::uint8_t> wall_cohesive;
  std::vector<ContactIndex> visit_order;  ///< reused by the passes, no allocation per step

  [[nodiscard]] std::size_t size() const { return pairs.size() + walls.size(); }

  void clear() {
    pairs.clear();
    pair_actions.clear();
    pair_cohesive.clear();
    walls.clear();
    wall_actions.clear();
    wall_cohesive.clear();
  }
};

/// The record of pair k of the actions' order where `record_of` names it (a coloured solve keeps
/// the records in storage order and the actions in colour order: ColouredPass::record_of); null:
/// the two orders are one.
inline const PairProblem& pair_record_at(const Contacts& contacts, const ContactIndex* record_of,
                                         std::size_t k) {
  return contacts.pairs[record_of != nullptr ? record_of[k] : k];
}

}  // namespace cdpowder
