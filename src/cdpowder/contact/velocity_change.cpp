// velocity_change.cpp — a whole action applied (out of line, as the warm start and the
// mixing call it once per contact).
#include "cdpowder/contact/velocity_change.hpp"

namespace cdpowder {

void apply_pair_action(const PairProblem& p, const ContactAction& delta, VelocityCache& v) {
  apply_pair_delta(p, delta.normal_force * p.normal + delta.tangential_force,
                   delta.rolling_torque + delta.twisting_torque * p.normal, v.spheres[p.a],
                   v.spheres[p.b]);
}

void apply_wall_action(const WallProblem& w, const ContactAction& delta, VelocityCache& v) {
  apply_wall_action(w, delta, v.spheres[w.sphere], v.piston_velocity);
}

void apply_wall_action(const WallProblem& w, const ContactAction& delta, SphereVelocity& s,
                       double& wall_velocity) {
  apply_wall_delta(w, delta.normal_force * w.normal + delta.tangential_force,
                   delta.rolling_torque + delta.twisting_torque * w.normal, s, wall_velocity);
}

}  // namespace cdpowder
