// build.cpp — per-contact constants, cohesion activity, warm start, predicted velocities.
#include "cdpowder/solver/build.hpp"

#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/core/assert.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

namespace {

/// Gaps below this count as touching: g_pos = 0 (UK03 eq. 33 with a dead band) [R].
/// Closed contacts that roll or slide open tiny gaps at second order, ≈ (ω Δt)² R per
/// step, because the geometry is frozen within a step (physics.md §3). The closing target
/// g/Δt of such a gap conflicts with the other constraints of a loop of closed, sticking
/// contacts (e.g. two spheres touching each other and the piston): the normal constraints
/// have no exact solution and the NLGS drifts the loop's forces by a constant amount per
/// sweep without ever meeting its stopping rule (found in capped compaction steps). Below
/// the dead band the contact is treated as touching. 1e-6 R is three orders below the
/// overlap accuracy target (mean overlap ≤ 1e-3 R, physics.md §17) and four below d_coh.
/// Measured on a 100-sphere compaction at (μ_t, μ_n) = (0, 0): total sweeps 19.1 M → 9.3 M,
/// capped steps 6823 → 1944, final porosity 0.69915 → 0.69939 (docs/performance.md).
constexpr double kTouchingGap = 1e-6;

/// g_pos/Δt: the approach speed that just closes an open gap within the step [R/t0].
double gap_closing_rate(double gap, double dt) {
  return gap > kTouchingGap ? gap / dt : 0.0;
}

/// Cohesion activity of a contact from its start-of-step gap (physics.md §6.2). Exactly
/// touching deposit contacts have |g| ~ 1e-15; `g ≤ d_coh` keeps round-off out of it (§12.11).
bool is_cohesive(const ContactLaw& law, CohesionRule rule, double gap, const CachedAction* last) {
  if (law.cohesion_force <= 0.0) return false;
  switch (rule) {
    case CohesionRule::Graph:
      return gap <= law.cohesion_range;
    case CohesionRule::History:
      // a bond forms at touching, in the sense the contact law uses (the dead band above):
      // with `g ≤ 0` the sign of round-off decided it, and about half of a deposit's exactly
      // touching contacts (|g| ~ 1e-15) started the compaction without cohesion
      return gap <= kTouchingGap ||
             (last != nullptr && last->cohesive && gap <= law.cohesion_range);
  }
  return false;
}

/// Warm start: last step's action, with its tangential parts projected onto the new
/// tangent plane (physics.md §7.4), written into `action`.
void warm_start(const CachedAction& last, const Vec3& n, double cohesion, ContactAction& action) {
  action = last.action;
  action.tangential_force -= action.tangential_force.dot(n) * n;
  action.rolling_torque -= action.rolling_torque.dot(n) * n;
  // an attraction may only be warm-started where this step's law allows it
  if (action.normal_force < -cohesion) action.normal_force = -cohesion;
}

/// What apply_pair_action and apply_wall_action do with a zero action (every field +0), without
/// the products. Their ΔR = (+0)·n + (+0) and ΔT = (+0) + (+0)·n are +0 in every component (a
/// signed zero plus +0 is +0), as is every product of them with a finite lever or normal,
/// summed with +0, and with Δt/m, Δt/I ≥ 0: body a gets x − (+0), which is x for every x, and
/// the sphere b (or the wall's sphere) gets x + (+0), which is x except that −0 becomes +0; the
/// piston's x − (+0) is x. Adding +0 to the sphere's six components gives those bits without
/// the ≈ 100 instructions of the full update, for every contact that was not in the last step's
/// cache (or every contact, without the warm start).
void apply_zero_action(SphereVelocity& s) {
  s.linear += Vec3(0.0, 0.0, 0.0);
  s.angular += Vec3(0.0, 0.0, 0.0);
}

void predict_velocities(const World& world, double dt, VelocityCache& velocities) {
  const Bodies& bodies = world.bodies;
  velocities.spheres.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    SphereVelocity& s = velocities.spheres[i];
    if (bodies.fixed[i] != 0) {
      s = SphereVelocity{};  // fixed: never moves, absorbs any action
      continue;
    }
    s.dt_inverse_mass = dt * bodies.inverse_mass[i];
    s.dt_inverse_inertia = dt * bodies.inverse_inertia[i];
    s.linear =
        bodies.velocity[i] + s.dt_inverse_mass * bodies.external_force[i] + dt * world.gravity;
    s.angular = bodies.angular_velocity[i] + s.dt_inverse_inertia * bodies.external_torque[i];
  }
  const Piston& piston = world.walls.piston;
  velocities.piston_velocity =
      piston.enabled
          ? piston.velocity + dt * (-piston.force * piston.inverse_mass() + world.gravity.z())
          : 0.0;
}

}  // namespace

void build_local_problems(const World& world, const StepSettings& settings, ActionCache& cache,
                          Contacts& contacts, VelocityCache& velocities) {
  const double dt = settings.solver.dt;
  const ContactLaws& laws = settings.laws;
  predict_velocities(world, dt, velocities);
  cache.rewind();

  contacts.pair_actions.resize(contacts.pairs.size());
  contacts.pair_cohesive.resize(contacts.pairs.size());
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    PairProblem& p = contacts.pairs[k];
    const SphereVelocity& a = velocities.spheres[p.a];
    const SphereVelocity& b = velocities.spheres[p.b];
    // W blocks of physics.md §5.2, times Δt, with the levers to the common contact point:
    // w_n = 1/m_a + 1/m_b, w_t = w_n + l_a²/I_a + l_b²/I_b, w_r = 1/I_a + 1/I_b
    const double dt_w_n = a.dt_inverse_mass + b.dt_inverse_mass;
    const double dt_w_t = dt_w_n + p.lever_a * p.lever_a * a.dt_inverse_inertia +
                          p.lever_b * p.lever_b * b.dt_inverse_inertia;
    const double dt_w_r = a.dt_inverse_inertia + b.dt_inverse_inertia;
    p.inv_dt_w_n = 1.0 / dt_w_n;
    p.inv_dt_w_t = 1.0 / dt_w_t;
    p.inv_dt_w_r = 1.0 / dt_w_r;
    p.gap_rate = gap_closing_rate(p.gap, dt);
    p.mu = laws.spheres.mu;
    p.roll_cap = laws.spheres.mu_roll * p.r_eff;
    p.twist_cap = laws.spheres.mu_twist * p.r_eff;
    const CachedAction* last =
        settings.solver.warm_start || laws.cohesion_rule == CohesionRule::History
            ? cache.find_pair(pair_key(p.a, p.b))
            : nullptr;
    const bool cohesive = is_cohesive(laws.spheres, laws.cohesion_rule, p.gap, last);
    p.cohesion = cohesive ? laws.spheres.cohesion_force : 0.0;
    contacts.pair_cohesive[k] = cohesive ? 1 : 0;
    ContactAction& action = contacts.pair_actions[k];
    if (settings.solver.warm_start && last != nullptr) {
      warm_start(*last, p.normal, p.cohesion, action);
      apply_pair_delta(p, action.normal_force * p.normal + action.tangential_force,
                       action.rolling_torque + action.twisting_torque * p.normal,
                       velocities.spheres[p.a], velocities.spheres[p.b]);
    } else {
      action = ContactAction{};
      apply_zero_action(velocities.spheres[p.b]);
    }
  }

  const double piston_response =
      world.walls.piston.enabled ? dt * world.walls.piston.inverse_mass() : 0.0;
  contacts.wall_actions.resize(contacts.walls.size());
  contacts.wall_cohesive.resize(contacts.walls.size());
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    WallProblem& w = contacts.walls[k];
    const SphereVelocity& s = velocities.spheres[w.sphere];
    w.wall_response = w.wall == WallKind::Piston ? piston_response : 0.0;
    w.wall_moves = w.wall == WallKind::Piston ? 1.0 : 0.0;
    // the wall is immobile tangentially and does not rotate; the piston moves along n
    const double dt_w_n = s.dt_inverse_mass + w.wall_response;
    const double dt_w_t = s.dt_inverse_mass + w.radius * w.radius * s.dt_inverse_inertia;
    const double dt_w_r = s.dt_inverse_inertia;
    w.inv_dt_w_n = dt_w_n > 0.0 ? 1.0 / dt_w_n : 0.0;
    w.inv_dt_w_t = dt_w_t > 0.0 ? 1.0 / dt_w_t : 0.0;
    w.inv_dt_w_r = dt_w_r > 0.0 ? 1.0 / dt_w_r : 0.0;
    w.gap_rate = gap_closing_rate(w.gap, dt);
    const double r_eff = laws.wall_r_eff_factor * w.radius;
    w.mu = laws.walls.mu;
    w.roll_cap = laws.walls.mu_roll * r_eff;
    w.twist_cap = laws.walls.mu_twist * r_eff;
    const CachedAction* last =
        settings.solver.warm_start || laws.cohesion_rule == CohesionRule::History
            ? cache.find_wall(wall_key(w.wall, w.sphere))
            : nullptr;
    const bool cohesive = is_cohesive(laws.walls, laws.cohesion_rule, w.gap, last);
    w.cohesion = cohesive ? laws.walls.cohesion_force : 0.0;
    contacts.wall_cohesive[k] = cohesive ? 1 : 0;
    ContactAction& action = contacts.wall_actions[k];
    if (settings.solver.warm_start && last != nullptr) {
      warm_start(*last, w.normal, w.cohesion, action);
      apply_wall_action(w, action, velocities);
    } else {
      action = ContactAction{};
      apply_zero_action(velocities.spheres[w.sphere]);
    }
  }
  // the sweeps assume finite v*, ω* (debug builds only; one pass over the spheres)
  CDP_ASSERT(std::isfinite(velocities.piston_velocity) &&
                 std::all_of(velocities.spheres.begin(), velocities.spheres.end(),
                             [](const SphereVelocity& s) {
                               return s.linear.allFinite() && s.angular.allFinite();
                             }),
             "non-finite predicted velocity");
}

void apply_pair_action(const PairProblem& p, const ContactAction& delta, VelocityCache& v) {
  apply_pair_delta(p, delta.normal_force * p.normal + delta.tangential_force,
                   delta.rolling_torque + delta.twisting_torque * p.normal, v.spheres[p.a],
                   v.spheres[p.b]);
}

void apply_wall_action(const WallProblem& w, const ContactAction& delta, VelocityCache& v) {
  apply_wall_delta(w, delta.normal_force * w.normal + delta.tangential_force,
                   delta.rolling_torque + delta.twisting_torque * w.normal, v.spheres[w.sphere],
                   v.piston_velocity);
}

}  // namespace cdpowder
