// summary.cpp — assembling summary.json with nlohmann::json (escaping, number formatting).
#include "cdpowder/io/summary.hpp"

#include "cdpowder/analysis/coordination.hpp"
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/experiment/deposition.hpp"
#include "cdpowder/version.hpp"

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <sstream>

namespace cdpowder {

namespace {

nlohmann::json matrix(const Mat3& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2)});
  return rows;
}

/// The effective scene as a JSON object (toml++ converts), so tools need no TOML parser.
nlohmann::json scene_json(const Scene& scene) {
  std::ostringstream text;
  text << toml::json_formatter{toml::parse(scene.effective_toml)};
  return nlohmann::json::parse(text.str());
}

/// The normal forces the spheres put on each wall, per area of the cell: what σzz should
/// equal in a packing at rest between them (their mean under the packing's own weight)
/// [F_coh/R²].
struct WallLoads {
  double piston = 0.0;
  double bottom = 0.0;
};

WallLoads wall_loads_per_area(const Contacts& contacts, double area) {
  WallLoads loads;
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const double push = contacts.wall_actions[k].normal_force;
    (contacts.walls[k].wall == WallKind::Piston ? loads.piston : loads.bottom) += push;
  }
  loads.piston /= area;
  loads.bottom /= area;
  return loads;
}

nlohmann::json fault_json(const RunFault& f) {
  const auto index = [](std::int64_t i) { return i >= 0 ? nlohmann::json(i) : nullptr; };
  return {{"quantity", f.quantity}, {"sphere", index(f.body)}, {"other_sphere", index(f.other)},
          {"step", f.step},         {"time", f.time},          {"value", f.value},
          {"message", f.message}};
}

}  // namespace

std::string summary_json(const Scene& scene, const World& world, const Contacts& contacts,
                         const RunResult& result, double initial_porosity) {
  const double volume = packing_volume(world);
  const StressTensors sigma = stress_tensors(contacts, volume);
  const StepDiagnostics& d = result.last.diagnostics;
  const Piston& piston = world.walls.piston;
  const double pressure = piston.enabled ? piston.force / world.box.area() : 0.0;

  nlohmann::json j;
  j["program"] = {{"name", "cdpowder"}, {"version", kVersion}, {"commit", kGitCommit}};
  j["seed"] = scene.step.solver.seed;
  j["porosity"] = porosity(world);
  j["initial_porosity"] = initial_porosity;
  j["packing_volume"] = volume;
  j["spheres"] = world.bodies.size();
  j["time"] = world.time;
  j["piston"] = {{"enabled", piston.enabled},
                 {"height", piston.height},
                 {"velocity", piston.velocity},
                 {"applied_force", piston.force},
                 {"applied_pressure", pressure},
                 // the push plus the piston's weight: what the spheres carry at rest
                 {"load", piston.enabled ? piston_load(world) : 0.0},
                 {"contact_force", d.piston_contact_force},
                 {"force_imbalance", d.piston_imbalance}};
  j["stress"] = {{"volume", volume},
                 {"sigma", matrix(sigma.total)},
                 {"sigma_compressive", matrix(sigma.compressive)},
                 {"sigma_tensile", matrix(sigma.tensile)},
                 {"compressive_contacts", sigma.compressive_contacts},
                 {"tensile_contacts", sigma.tensile_contacts}};
  const WallLoads loads = wall_loads_per_area(contacts, world.box.area());
  j["stress"]["piston_load_per_area"] = loads.piston;
  j["stress"]["bottom_load_per_area"] = loads.bottom;
  if (pressure > 0.0) {
    j["stress"]["sigma_zz_over_pressure"] = sigma.total(2, 2) / pressure;
    j["stress"]["sigma_zz_compressive_over_pressure"] = sigma.compressive(2, 2) / pressure;
    j["stress"]["sigma_zz_tensile_over_pressure"] = sigma.tensile(2, 2) / pressure;
  }
  j["contacts"] = {{"candidates", d.contacts},
                   {"closed", d.closed_contacts},
                   {"cohesive", d.cohesive_contacts},
                   {"coordination_number", coordination_number(contacts, world.bodies.size())}};
  j["accuracy"] = {{"mean_overlap", d.mean_overlap},
                   {"max_overlap", d.max_overlap},
                   {"max_overlap_during_run", result.max_overlap_seen},
                   {"max_net_force", d.max_net_force},
                   {"max_cohesive_opening_per_range", result.max_cohesive_opening_per_range},
                   {"last_step_residual", result.last.solver.residual},
                   {"last_step_error_estimate", result.last.solver.error_estimate},
                   {"last_step_converged", result.last.solver.converged},
                   {"capped_steps", result.capped_steps}};
  // the step solved to run.blocked.final_tolerance once blocked (null otherwise): the
  // forces the stress above is measured on
  j["accuracy"]["final_solve"] = nullptr;
  if (result.final_solve) {
    j["accuracy"]["final_solve"] = {{"sweeps", result.final_solve->sweeps},
                                    {"converged", result.final_solve->converged},
                                    {"residual", result.final_solve->residual},
                                    {"error_estimate", result.final_solve->error_estimate}};
  }
  j["kinetic_energy"] = d.kinetic_energy;
  j["max_speed"] = d.max_speed;
  j["rms_speed"] = d.rms_speed;
  j["run"] = {
      {"blocked", result.blocked},
      // which test found the rest: the window mean of the force imbalance, or a static
      // probe of it (run_loop.cpp); null when not blocked
      {"blocked_by", result.blocked ? nlohmann::json(result.blocked_by_probe ? "probe" : "window")
                                    : nlohmann::json(nullptr)},
      {"probes", result.probes},
      {"probe_sweeps", result.probe_sweeps},
      {"probe_seconds", result.probe_seconds},
      // static solves of a resting packing that were not adopted because a sphere was out
      // of balance in them (run_loop.cpp)
      {"unbalanced_rest_solves", result.unbalanced_rest_solves},
      {"interrupted", result.interrupted},
      // a fault ended the run (the "fault" object says which, where and when)
      {"failed", result.fault.has_value()},
      {"until_blocked", scene.run.until_blocked},
      {"steps", result.steps},
      // Δt of the steps: equal without solver.adaptive_dt [t0]
      {"dt_min", result.min_dt},
      {"dt_max", result.max_dt},
      // adaptive Δt: steps undone and repeated with a shorter Δt, and their sweeps (not in
      // steps and total_sweeps)
      {"repeated_steps", result.repeated_steps},
      {"repeated_sweeps", result.repeated_sweeps},
      {"total_sweeps", result.total_sweeps},
      {"sweeps_per_step", result.steps > 0 ? static_cast<double>(result.total_sweeps) /
                                                 static_cast<double>(result.steps)
                                           : 0.0},
      {"wall_seconds", result.wall_seconds},
      {"stage_seconds",
       {{"detect_contacts", result.stage_seconds[0]},
        {"build_local_problems", result.stage_seconds[1]},
        {"solve_nlgs", result.stage_seconds[2]},
        {"integrate", result.stage_seconds[3]},
        {"analyse", result.stage_seconds[4]}}}};
  j["fault"] = result.fault ? fault_json(*result.fault) : nullptr;
  j["scene"] = scene_json(scene);
  j["scene_toml"] = scene.effective_toml;
  return j.dump(2) + "\n";
}

std::string deposit_summary_json(const Scene& scene, const World& world) {
  nlohmann::json j;
  j["program"] = {{"name", "cdpowder"}, {"version", kVersion}, {"commit", kGitCommit}};
  j["seed"] = scene.deposition ? scene.deposition->seed : 0;
  j["spheres"] = world.bodies.size();
  j["porosity"] = deposit_porosity(world.bodies, world.box);
  j["height"] = deposit_height(world.bodies);
  j["grain_volume"] = grain_volume(world.bodies);
  j["scene"] = scene_json(scene);
  j["scene_toml"] = scene.effective_toml;
  return j.dump(2) + "\n";
}

}  // namespace cdpowder
