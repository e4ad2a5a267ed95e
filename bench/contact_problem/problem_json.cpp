// problem_json.cpp — field-by-field JSON of the contact records; doubles are written in
// nlohmann-json's shortest round-trip form, so a problem reads back bit for bit.
#include "contact_problem/problem_json.hpp"

#include "cdpowder/contact/velocity_change.hpp"

#include <fstream>
#include <stdexcept>

namespace cdpowder::bench {

namespace {

using nlohmann::json;

json vec(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

Vec3 vec_from(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

/// Column `key` of a struct-of-arrays table: one value per record.
template <typename Record, typename Get>
json column(const std::vector<Record>& records, Get get) {
  json out = json::array();
  for (const Record& r : records) out.push_back(get(r));
  return out;
}

json velocities_json(const VelocityCache& v) {
  json out;
  out["linear"] = column(v.spheres, [](const SphereVelocity& s) { return vec(s.linear); });
  out["angular"] = column(v.spheres, [](const SphereVelocity& s) { return vec(s.angular); });
  out["dt_inverse_mass"] =
      column(v.spheres, [](const SphereVelocity& s) { return s.dt_inverse_mass; });
  out["dt_inverse_inertia"] =
      column(v.spheres, [](const SphereVelocity& s) { return s.dt_inverse_inertia; });
  out["piston"] = v.piston_velocity;
  return out;
}

VelocityCache velocities_from(const json& j) {
  VelocityCache v;
  const std::size_t n = j.at("linear").size();
  v.spheres.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    SphereVelocity& s = v.spheres[i];
    s.linear = vec_from(j.at("linear").at(i));
    s.angular = vec_from(j.at("angular").at(i));
    s.dt_inverse_mass = j.at("dt_inverse_mass").at(i).get<double>();
    s.dt_inverse_inertia = j.at("dt_inverse_inertia").at(i).get<double>();
  }
  v.piston_velocity = j.at("piston").get<double>();
  return v;
}

json pairs_json(const std::vector<PairProblem>& pairs) {
  json out;
  out["a"] = column(pairs, [](const PairProblem& p) { return p.a; });
  out["b"] = column(pairs, [](const PairProblem& p) { return p.b; });
  out["normal"] = column(pairs, [](const PairProblem& p) { return vec(p.normal); });
  out["gap"] = column(pairs, [](const PairProblem& p) { return p.gap; });
  out["gap_rate"] = column(pairs, [](const PairProblem& p) { return p.gap_rate; });
  out["lever_a"] = column(pairs, [](const PairProblem& p) { return p.lever_a; });
  out["lever_b"] = column(pairs, [](const PairProblem& p) { return p.lever_b; });
  out["inv_dt_w_n"] = column(pairs, [](const PairProblem& p) { return p.inv_dt_w_n; });
  out["inv_dt_w_t"] = column(pairs, [](const PairProblem& p) { return p.inv_dt_w_t; });
  out["inv_dt_w_r"] = column(pairs, [](const PairProblem& p) { return p.inv_dt_w_r; });
  out["cohesion"] = column(pairs, [](const PairProblem& p) { return p.cohesion; });
  out["mu"] = column(pairs, [](const PairProblem& p) { return p.mu; });
  out["roll_cap"] = column(pairs, [](const PairProblem& p) { return p.roll_cap; });
  out["twist_cap"] = column(pairs, [](const PairProblem& p) { return p.twist_cap; });
  out["r_eff"] = column(pairs, [](const PairProblem& p) { return p.r_eff; });
  return out;
}

std::vector<PairProblem> pairs_from(const json& j) {
  std::vector<PairProblem> pairs(j.at("a").size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    PairProblem& p = pairs[k];
    const auto at = [&](const char* key) { return j.at(key).at(k).get<double>(); };
    p.a = j.at("a").at(k).get<BodyIndex>();
    p.b = j.at("b").at(k).get<BodyIndex>();
    p.normal = vec_from(j.at("normal").at(k));
    p.gap = at("gap");
    p.gap_rate = at("gap_rate");
    p.lever_a = at("lever_a");
    p.lever_b = at("lever_b");
    p.inv_dt_w_n = at("inv_dt_w_n");
    p.inv_dt_w_t = at("inv_dt_w_t");
    p.inv_dt_w_r = at("inv_dt_w_r");
    p.cohesion = at("cohesion");
    p.mu = at("mu");
    p.roll_cap = at("roll_cap");
    p.twist_cap = at("twist_cap");
    p.r_eff = at("r_eff");
  }
  return pairs;
}

json walls_json(const std::vector<WallProblem>& walls) {
  json out;
  out["sphere"] = column(walls, [](const WallProblem& w) { return w.sphere; });
  out["wall"] = column(
      walls, [](const WallProblem& w) { return w.wall == WallKind::Piston ? "piston" : "bottom"; });
  out["normal"] = column(walls, [](const WallProblem& w) { return vec(w.normal); });
  out["gap"] = column(walls, [](const WallProblem& w) { return w.gap; });
  out["gap_rate"] = column(walls, [](const WallProblem& w) { return w.gap_rate; });
  out["radius"] = column(walls, [](const WallProblem& w) { return w.radius; });
  out["inv_dt_w_n"] = column(walls, [](const WallProblem& w) { return w.inv_dt_w_n; });
  out["inv_dt_w_t"] = column(walls, [](const WallProblem& w) { return w.inv_dt_w_t; });
  out["inv_dt_w_r"] = column(walls, [](const WallProblem& w) { return w.inv_dt_w_r; });
  out["cohesion"] = column(walls, [](const WallProblem& w) { return w.cohesion; });
  out["mu"] = column(walls, [](const WallProblem& w) { return w.mu; });
  out["roll_cap"] = column(walls, [](const WallProblem& w) { return w.roll_cap; });
  out["twist_cap"] = column(walls, [](const WallProblem& w) { return w.twist_cap; });
  out["wall_response"] = column(walls, [](const WallProblem& w) { return w.wall_response; });
  out["wall_moves"] = column(walls, [](const WallProblem& w) { return w.wall_moves; });
  return out;
}

std::vector<WallProblem> walls_from(const json& j) {
  std::vector<WallProblem> walls(j.at("sphere").size());
  for (std::size_t k = 0; k < walls.size(); ++k) {
    WallProblem& w = walls[k];
    const auto at = [&](const char* key) { return j.at(key).at(k).get<double>(); };
    w.sphere = j.at("sphere").at(k).get<BodyIndex>();
    w.wall =
        j.at("wall").at(k).get<std::string>() == "piston" ? WallKind::Piston : WallKind::Bottom;
    w.normal = vec_from(j.at("normal").at(k));
    w.gap = at("gap");
    w.gap_rate = at("gap_rate");
    w.radius = at("radius");
    w.inv_dt_w_n = at("inv_dt_w_n");
    w.inv_dt_w_t = at("inv_dt_w_t");
    w.inv_dt_w_r = at("inv_dt_w_r");
    w.cohesion = at("cohesion");
    w.mu = at("mu");
    w.roll_cap = at("roll_cap");
    w.twist_cap = at("twist_cap");
    w.wall_response = at("wall_response");
    w.wall_moves = at("wall_moves");
  }
  return walls;
}

}  // namespace

json actions_to_json(const ContactActions& actions) {
  json out;
  out["normal_force"] = column(actions, [](const ContactAction& a) { return a.normal_force; });
  out["tangential_force"] =
      column(actions, [](const ContactAction& a) { return vec(a.tangential_force); });
  out["rolling_torque"] =
      column(actions, [](const ContactAction& a) { return vec(a.rolling_torque); });
  out["twisting_torque"] =
      column(actions, [](const ContactAction& a) { return a.twisting_torque; });
  return out;
}

ContactActions actions_from_json(const json& j) {
  ContactActions actions(j.at("normal_force").size());
  for (std::size_t k = 0; k < actions.size(); ++k) {
    ContactAction& a = actions[k];
    a.normal_force = j.at("normal_force").at(k).get<double>();
    a.tangential_force = vec_from(j.at("tangential_force").at(k));
    if (j.contains("rolling_torque")) a.rolling_torque = vec_from(j.at("rolling_torque").at(k));
    if (j.contains("twisting_torque")) {
      a.twisting_torque = j.at("twisting_torque").at(k).get<double>();
    }
  }
  return actions;
}

ContactActions actions_of(const Contacts& contacts) {
  ContactActions out(contacts.pair_actions);
  out.insert(out.end(), contacts.wall_actions.begin(), contacts.wall_actions.end());
  return out;
}

void set_actions(const ContactActions& actions, Contacts& contacts) {
  if (actions.size() != contacts.size()) {
    throw std::runtime_error("the solution has " + std::to_string(actions.size()) +
                             " actions, the problem " + std::to_string(contacts.size()) +
                             " contacts");
  }
  const auto pairs = static_cast<std::ptrdiff_t>(contacts.pairs.size());
  contacts.pair_actions.assign(actions.begin(), actions.begin() + pairs);
  contacts.wall_actions.assign(actions.begin() + pairs, actions.end());
}

VelocityCache velocities_for(const Contacts& contacts, VelocityCache velocities) {
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    apply_pair_action(contacts.pairs[k], contacts.pair_actions[k], velocities);
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    apply_wall_action(contacts.walls[k], contacts.wall_actions[k], velocities);
  }
  return velocities;
}

json to_json(const ContactProblem& problem) {
  json out;
  out["format"] = "cdpowder contact problem 1";
  out["scene_toml"] = problem.scene_toml;
  out["sweep_order_rng"] = problem.sweep_order_rng;
  out["step_index"] = problem.step_index;
  out["dt"] = problem.dt;
  out["reference_force"] = problem.reference_force;
  out["sphere_cohesion_range"] = problem.sphere_cohesion_range;
  out["wall_cohesion_range"] = problem.wall_cohesion_range;
  out["piston_force"] = problem.piston_force;
  out["piston_velocity"] = problem.piston_velocity;
  out["pairs"] = pairs_json(problem.contacts.pairs);
  out["walls"] = walls_json(problem.contacts.walls);
  out["warm_start"] = actions_to_json(actions_of(problem.contacts));
  out["free_velocities"] = velocities_json(problem.free_velocities);
  out["start_velocities"] = velocities_json(problem.start_velocities);
  out["velocity"] = column(problem.velocity, [](const Vec3& v) { return vec(v); });
  out["angular_velocity"] = column(problem.angular_velocity, [](const Vec3& v) { return vec(v); });
  out["radius"] = problem.radius;
  return out;
}

ContactProblem contact_problem_from_json(const json& j) {
  const auto format = j.find("format");
  if (format == j.end() || *format != "cdpowder contact problem 1") {
    throw std::runtime_error("not a cdpowder contact problem (format 1)");
  }
  ContactProblem p;
  p.scene_toml = j.at("scene_toml").get<std::string>();
  p.sweep_order_rng = j.at("sweep_order_rng").get<std::string>();
  p.step_index = j.at("step_index").get<std::int64_t>();
  p.dt = j.at("dt").get<double>();
  p.reference_force = j.at("reference_force").get<double>();
  p.sphere_cohesion_range = j.at("sphere_cohesion_range").get<double>();
  p.wall_cohesion_range = j.at("wall_cohesion_range").get<double>();
  p.piston_force = j.at("piston_force").get<double>();
  p.piston_velocity = j.at("piston_velocity").get<double>();
  p.contacts.pairs = pairs_from(j.at("pairs"));
  p.contacts.walls = walls_from(j.at("walls"));
  p.contacts.pair_cohesive.resize(p.contacts.pairs.size());
  for (std::size_t k = 0; k < p.contacts.pairs.size(); ++k) {
    p.contacts.pair_cohesive[k] = p.contacts.pairs[k].cohesion > 0.0 ? 1 : 0;
  }
  p.contacts.wall_cohesive.resize(p.contacts.walls.size());
  for (std::size_t k = 0; k < p.contacts.walls.size(); ++k) {
    p.contacts.wall_cohesive[k] = p.contacts.walls[k].cohesion > 0.0 ? 1 : 0;
  }
  set_actions(actions_from_json(j.at("warm_start")), p.contacts);
  p.free_velocities = velocities_from(j.at("free_velocities"));
  p.start_velocities = velocities_from(j.at("start_velocities"));
  for (const json& v : j.at("velocity")) p.velocity.push_back(vec_from(v));
  for (const json& v : j.at("angular_velocity")) p.angular_velocity.push_back(vec_from(v));
  p.radius = j.at("radius").get<std::vector<double>>();
  return p;
}

json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  try {
    return json::parse(in);
  } catch (const json::exception& error) {
    throw std::runtime_error(path + ": " + error.what());
  }
}

void write_json_file(const std::string& path, const json& j) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << j.dump() << '\n';
  if (!out) throw std::runtime_error("write failed: " + path);
}

}  // namespace cdpowder::bench
