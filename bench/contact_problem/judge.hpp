// judge.hpp — one measure for any solution of an exported contact problem, whoever solved
// it: the residual the engine's stopping rule uses (one NLGS sweep from the solution,
// physics.md §7.3) and the solution's accuracy gauges (§17), all in the engine's units.
#pragma once

#include "contact_problem/problem_json.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace cdpowder::bench {

struct Judgement {
  /// Largest change of R_n, R_t, T_t/r_eff, T_n/r_eff in ONE sweep (no mixing) started from
  /// the solution, / force_scale: nlgs.cpp's residual (§7.3) [-]
  double residual = 0.0;
  /// F_ref = max(F_coh, mean |R_n| of the contacts closed after that sweep) [F_coh]
  double force_scale = 0.0;
  /// The same change, but each contact solved alone with all others at the solution
  /// (no Gauss–Seidel propagation): independent of the visiting order [-]
  double local_residual = 0.0;
  /// max over contacts of max(0, −(V_n + g_pos/Δt)) Δt: how far the step would push a
  /// contact beyond its target (an overlap created, or a gap closed too far) [R]
  double max_penetration = 0.0;
  /// max over closed contacts (S = R_n + F_c > 0) of max(0, V_n + g_pos/Δt) Δt: a loaded
  /// contact that separates [R]
  double max_separation = 0.0;
  /// mean and largest predicted overlap max(0, −(g + V_n Δt)) after the step, over closed
  /// contacts and over all contacts (§17 gauge, to first order in Δt) [R]
  double mean_overlap = 0.0;
  double max_overlap = 0.0;
  /// max over cohesion-active contacts of V_n Δt / d_coh (§6.4, §17) [-]
  double max_opening_per_range = 0.0;
  /// max over contacts of max(0, |R_t| − μ S, −S) / force_scale: how far an action lies
  /// outside the law's admissible set (S = R_n + F_c) [-]
  double max_law_violation = 0.0;
  /// |Σ R_c→P · e_z − F| / F, the piston's force balance (§17) [-]
  double piston_imbalance = 0.0;
  /// max_i m|v* − v|/Δt + I|ω* − ω|/(Δt R_i) over free spheres (§17) [F_coh]
  double max_net_force = 0.0;
  std::size_t closed = 0;  ///< contacts with S > 0 in the solution
};

/// Judges `actions` on `problem`: the velocity cache is v_free + Δt M⁻¹ Σ actions (§5.3),
/// then the gauges are read and one sweep is run in a block-random order from `seed`.
/// With presweeps = k > 0 the solution is first passed through k engine sweeps (in the same
/// order), and what they leave is judged: a solver's output followed by k sweeps, e.g. to
/// project an iterate that lies outside the contact law back onto it.
Judgement judge(const ContactProblem& problem, const ContactActions& actions, std::uint64_t seed,
                int presweeps = 0);

nlohmann::json to_json(const Judgement& judgement);

/// Per contact (combined order): the relative velocity V of the contact point [R/t0] and
/// g_pos/Δt, from v_free + Δt M⁻¹ Σ actions: what a mapping to another solver must reproduce.
nlohmann::json contact_velocities(const ContactProblem& problem, const ContactActions& actions);

}  // namespace cdpowder::bench
