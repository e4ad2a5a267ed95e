// judge.cpp — the residual and the gauges of a solution, from the engine's own kernels.
#include "contact_problem/judge.hpp"

#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/solver/nlgs/nlgs.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder::bench {

namespace {

/// Relative velocity of a wall contact's point (physics.md §5.1): V = v_s − R ω_s × n − V_P e_z.
Vec3 wall_relative_velocity(const WallProblem& w, const SphereVelocity& s, double piston_velocity) {
  return s.linear - w.radius * s.angular.cross(w.normal) -
         Vec3(0.0, 0.0, w.wall_moves * piston_velocity);
}

/// V of every contact (combined order) for the velocity cache `v`.
std::vector<Vec3> relative_velocities(const Contacts& contacts, const VelocityCache& v) {
  std::vector<Vec3> out;
  out.reserve(contacts.size());
  for (const PairProblem& p : contacts.pairs) {
    Vec3 V;
    Vec3 Omega;
    pair_relative_velocity(p, v.spheres[p.a], v.spheres[p.b], V, Omega);
    out.push_back(V);
  }
  for (const WallProblem& w : contacts.walls) {
    out.push_back(wall_relative_velocity(w, v.spheres[w.sphere], v.piston_velocity));
  }
  return out;
}

/// What one contact needs for the gauges, whatever its kind.
struct GaugeView {
  const Vec3& normal;
  double gap, gap_rate, cohesion, mu, cohesion_range;
};

/// Largest change of one contact solved alone, all other actions and velocities as given.
double local_change_sq(const Contacts& contacts, const VelocityCache& v, std::size_t k) {
  const std::size_t n_pairs = contacts.pairs.size();
  if (k < n_pairs) {
    const PairProblem& p = contacts.pairs[k];
    ContactAction action = contacts.pair_actions[k];
    SphereVelocity a = v.spheres[p.a];
    SphereVelocity b = v.spheres[p.b];
    return solve_pair(p, action, a, b).change_sq;
  }
  const WallProblem& w = contacts.walls[k - n_pairs];
  ContactAction action = contacts.wall_actions[k - n_pairs];
  SphereVelocity s = v.spheres[w.sphere];
  double piston = v.piston_velocity;
  return solve_wall(w, action, s, piston).change_sq;
}

void read_gauges(const ContactProblem& problem, const Contacts& contacts, const VelocityCache& v,
                 Judgement& out) {
  const std::vector<Vec3> V = relative_velocities(contacts, v);
  const ContactActions actions = actions_of(contacts);
  const double dt = problem.dt;
  double overlap_sum = 0.0;
  double piston_push = 0.0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const bool pair = k < contacts.pairs.size();
    const GaugeView c = pair ? GaugeView{contacts.pairs[k].normal,   contacts.pairs[k].gap,
                                         contacts.pairs[k].gap_rate, contacts.pairs[k].cohesion,
                                         contacts.pairs[k].mu,       problem.sphere_cohesion_range}
                             : GaugeView{contacts.walls[k - contacts.pairs.size()].normal,
                                         contacts.walls[k - contacts.pairs.size()].gap,
                                         contacts.walls[k - contacts.pairs.size()].gap_rate,
                                         contacts.walls[k - contacts.pairs.size()].cohesion,
                                         contacts.walls[k - contacts.pairs.size()].mu,
                                         problem.wall_cohesion_range};
    const ContactAction& a = actions[k];
    const double V_n = V[k].dot(c.normal);
    const double target = V_n + c.gap_rate;  // 0 if closed, ≥ 0 if open (§5.4 step 1)
    const double S = a.normal_force + c.cohesion;
    const double overlap = std::max(0.0, -(c.gap + V_n * dt));
    out.max_penetration = std::max(out.max_penetration, std::max(0.0, -target) * dt);
    out.max_overlap = std::max(out.max_overlap, overlap);
    if (S > 0.0) {
      ++out.closed;
      overlap_sum += overlap;
      out.max_separation = std::max(out.max_separation, std::max(0.0, target) * dt);
    }
    if (c.cohesion > 0.0 && c.cohesion_range > 0.0) {
      out.max_opening_per_range = std::max(out.max_opening_per_range, V_n * dt / c.cohesion_range);
    }
    const double outside = std::max(a.tangential_force.norm() - c.mu * std::max(S, 0.0), -S);
    out.max_law_violation = std::max(out.max_law_violation, outside);
    if (!pair && contacts.walls[k - contacts.pairs.size()].wall == WallKind::Piston) {
      piston_push += a.normal_force;  // n = −e_z: the force on the piston has z part +R_n
    }
  }
  out.mean_overlap = out.closed > 0 ? overlap_sum / static_cast<double>(out.closed) : 0.0;
  if (problem.piston_force > 0.0) {
    out.piston_imbalance = std::abs(piston_push - problem.piston_force) / problem.piston_force;
  }
  for (std::size_t i = 0; i < v.spheres.size(); ++i) {
    const SphereVelocity& s = v.spheres[i];
    if (s.dt_inverse_mass <= 0.0) continue;  // fixed sphere
    const double force = (s.linear - problem.velocity[i]).norm() / s.dt_inverse_mass;
    const double torque =
        (s.angular - problem.angular_velocity[i]).norm() / s.dt_inverse_inertia / problem.radius[i];
    out.max_net_force = std::max(out.max_net_force, force + torque);
  }
}

}  // namespace

Judgement judge(const ContactProblem& problem, const ContactActions& actions, std::uint64_t seed,
                int presweeps) {
  Contacts contacts = problem.contacts;
  set_actions(actions, contacts);
  VelocityCache velocities = velocities_for(contacts, problem.free_velocities);
  // the engine's default order (block-random, one permutation for the step)
  NlgsWorkspace work(seed);
  prepare_visit_order(contacts, VisitOrder::RandomEachStep, work);
  for (int k = 0; k < presweeps; ++k) run_scalar_pass(contacts, velocities);

  Judgement out;
  read_gauges(problem, contacts, velocities, out);
  double local_sq = 0.0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    local_sq = std::max(local_sq, local_change_sq(contacts, velocities, k));
  }

  const PassSums sums = run_scalar_pass(contacts, velocities);
  const double mean_closed =
      sums.closed > 0 ? sums.sum_closed_normal / static_cast<double>(sums.closed) : 0.0;
  out.force_scale = std::max({problem.reference_force, mean_closed, 1e-300});
  out.residual = std::sqrt(sums.max_change_sq) / out.force_scale;
  out.local_residual = std::sqrt(local_sq) / out.force_scale;
  out.max_law_violation /= out.force_scale;
  return out;
}

nlohmann::json to_json(const Judgement& j) {
  return {{"residual", j.residual},
          {"force_scale", j.force_scale},
          {"local_residual", j.local_residual},
          {"max_penetration", j.max_penetration},
          {"max_separation", j.max_separation},
          {"mean_overlap", j.mean_overlap},
          {"max_overlap", j.max_overlap},
          {"max_opening_per_range", j.max_opening_per_range},
          {"max_law_violation", j.max_law_violation},
          {"piston_imbalance", j.piston_imbalance},
          {"max_net_force", j.max_net_force},
          {"closed", j.closed}};
}

nlohmann::json contact_velocities(const ContactProblem& problem, const ContactActions& actions) {
  Contacts contacts = problem.contacts;
  set_actions(actions, contacts);
  const VelocityCache velocities = velocities_for(contacts, problem.free_velocities);
  const std::vector<Vec3> V = relative_velocities(contacts, velocities);
  nlohmann::json relative = nlohmann::json::array();
  nlohmann::json gap_rate = nlohmann::json::array();
  for (std::size_t k = 0; k < V.size(); ++k) {
    relative.push_back({V[k].x(), V[k].y(), V[k].z()});
    gap_rate.push_back(k < contacts.pairs.size()
                           ? contacts.pairs[k].gap_rate
                           : contacts.walls[k - contacts.pairs.size()].gap_rate);
  }
  return {{"relative_velocity", relative}, {"gap_rate", gap_rate}};
}

}  // namespace cdpowder::bench
