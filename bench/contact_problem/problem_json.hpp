// problem_json.hpp — one step's contact problem as the engine builds it (physics.md §5.2,
// §5.4, §7.6 stage 2), written to and read back from JSON, so that other solvers can be run
// on exactly the problem the NLGS solves (docs/performance.md, "Newton-type solvers").
//
// Units are the engine's (physics.md §2): forces [F_coh], velocities [R/t0], Δt/m
// [t0/(ρR³)], Δt/I [t0/(ρR⁵)]. The contact records are PairProblem and WallProblem field by
// field, so a reader gets the engine's kernels' inputs bit for bit.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace cdpowder::bench {

/// Everything of one step that a contact solver or a judge of its solution needs.
struct ContactProblem {
  std::string scene_toml;        ///< the resolved scene, for the solver settings
  std::string sweep_order_rng;   ///< the sweep-order stream before the solve (pcg32 text)
  std::int64_t step_index = 0;   ///< World::step at the start of the step
  double dt = 0.0;               ///< Δt [t0]
  double reference_force = 0.0;  ///< F_coh of sphere pairs: the floor of the force scale (§7.3)
  double sphere_cohesion_range = 0.0;  ///< d_coh of pairs [R] (§6.3)
  double wall_cohesion_range = 0.0;    ///< d_coh at the walls [R]
  double piston_force = 0.0;           ///< F, the piston's push along −z [F_coh] (0: none)

  /// The geometry, W diagonals and thresholds of every contact; the actions are the
  /// warm start (§7.4).
  Contacts contacts;
  /// v_free = v + Δt F_ext/m + Δt g and ω_free, V_P,free: no contact action applied (§5.3).
  VelocityCache free_velocities;
  /// v* of the engine before its first sweep: free_velocities plus the warm start, exactly as
  /// build_local_problems left them.
  VelocityCache start_velocities;
  std::vector<Vec3> velocity;          ///< v(t) at the start of the step [R/t0]
  std::vector<Vec3> angular_velocity;  ///< ω(t) [1/t0]
  std::vector<double> radius;          ///< R_i [R]
  double piston_velocity = 0.0;        ///< V_P(t) [R/t0]
};

/// One action per contact in the combined order (pairs, then walls).
using ContactActions = std::vector<ContactAction>;

nlohmann::json to_json(const ContactProblem& problem);
ContactProblem contact_problem_from_json(const nlohmann::json& j);

/// {"normal_force": [...], "tangential_force": [[x,y,z],...], "rolling_torque": [...],
///  "twisting_torque": [...]}; reading, missing torque arrays mean zero torques.
nlohmann::json actions_to_json(const ContactActions& actions);
ContactActions actions_from_json(const nlohmann::json& j);

/// The actions of a contact set in the combined order, and back.
ContactActions actions_of(const Contacts& contacts);
void set_actions(const ContactActions& actions, Contacts& contacts);

/// `velocities` plus Δt M⁻¹ Σ (contact actions) on both bodies of every contact: the
/// velocity cache the engine keeps for these actions (§5.3).
VelocityCache velocities_for(const Contacts& contacts, VelocityCache velocities);

/// Reads and writes a JSON file; throws std::runtime_error naming the file.
nlohmann::json read_json_file(const std::string& path);
void write_json_file(const std::string& path, const nlohmann::json& j);

}  // namespace cdpowder::bench
