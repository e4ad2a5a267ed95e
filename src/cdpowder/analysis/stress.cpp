// stress.cpp — contact stress from the step's frozen geometry and solved forces.
#include "cdpowder/analysis/stress.hpp"

#include "cdpowder/contact/contact_view.hpp"

namespace cdpowder {

namespace {

void add_contact(StressTensors& s, const Vec3& n, const ContactAction& action, double branch,
                 double cohesion) {
  // an open, non-cohesive candidate carries nothing and is neither kind
  const bool carries = action.normal_force != 0.0 || is_closed(action.normal_force, cohesion);
  if (!carries) return;
  const Vec3 force = action.normal_force * n + action.tangential_force;
  const Mat3 term = force * (branch * n).transpose();
  s.total += term;
  if (action.normal_force >= 0.0) {
    s.compressive += term;
    ++s.compressive_contacts;
  } else {
    s.tensile += term;
    ++s.tensile_contacts;
  }
}

}  // namespace

StressTensors stress_tensors(const Contacts& contacts, double volume) {
  StressTensors s;
  // branch length |d| = R_a + R_b + g = |l_a| + |l_b|, or R + g from a wall
  for_each_contact(contacts, [&](const ContactView& c) {
    add_contact(s, c.normal, *c.action, c.branch, c.cohesion);
  });
  if (volume > 0.0) {
    s.total /= volume;
    s.compressive /= volume;
    s.tensile /= volume;
  }
  return s;
}

}  // namespace cdpowder
