// velocity_change.cpp — a whole action applied (out of line, as the warm start and the
// mixing call it once per contact).
#include "cdpowder/contact/velocity_change.hpp"

namespace cdpowder {

void apply_pair_action(const PairProblem& p, const ContactAction& delta, VelocityCache& v) {
  apply_pair_delta(p, action_force(delta, p.normal), action_torque(delta, p.normal), v.spheres[p.a],
                   v.spheres[p.b]);
}

void apply_wall_action(const WallProblem& w, const ContactAction& delta, VelocityCache& v) {
  apply_wall_action(w, delta, v.spheres[w.sphere], v.piston_velocity);
}

void apply_wall_action(const WallProblem& w, const ContactAction& delta, SphereVelocity& s,
                       double& wall_velocity) {
  apply_wall_delta(w, action_force(delta, w.normal), action_torque(delta, w.normal), s,
                   wall_velocity);
}

}  // namespace cdpowder
