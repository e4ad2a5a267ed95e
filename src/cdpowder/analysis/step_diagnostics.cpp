// step_diagnostics.cpp — overlaps from the new positions, the piston balance, and the
// spheres' measures joined in.
#include "cdpowder/analysis/step_diagnostics.hpp"

#include "cdpowder/contact/contact_view.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

void measure_contacts(const World& world, const Contacts& contacts, StepDiagnostics& d) {
  const Bodies& bodies = world.bodies;
  const Piston& piston = world.walls.piston;
  d.contacts = contacts.size();
  double overlap_sum = 0.0;
  // pairs, then walls: overlap_sum and the piston's force add up in Contacts' order
  for_each_contact(contacts, [&](const ContactView& c) {
    // the overlap from the new positions (c.gap is the step's start)
    double overlap = 0.0;
    if (c.is_pair()) {
      const Vec3 d_ab = world.box.minimum_image(bodies.position[c.b] - bodies.position[c.a]);
      overlap = std::max(0.0, bodies.radius[c.a] + bodies.radius[c.b] - d_ab.norm());
    } else {
      // detect_contacts gives a wall contact its sphere's radius
      const double z = bodies.position[c.b].z();
      const double r = bodies.radius[c.b];
      const double gap = *c.wall == WallKind::Bottom ? z - r : piston.height - z - r;
      overlap = std::max(0.0, -gap);
    }
    d.max_overlap = std::max(d.max_overlap, overlap);
    if (c.cohesive) ++d.cohesive_contacts;
    if (c.closed()) {
      ++d.closed_contacts;
      overlap_sum += overlap;
    }
    // n = −e_z at the piston: the force on the piston is −R, its z part +R_n
    if (c.wall == WallKind::Piston) d.piston_contact_force += c.action->normal_force;
  });
  d.mean_overlap =
      d.closed_contacts > 0 ? overlap_sum / static_cast<double>(d.closed_contacts) : 0.0;
}

StepDiagnostics join_measures(const World& world, const StepDiagnostics& of_contacts,
                              const SphereMeasures& of_spheres) {
  StepDiagnostics d = of_contacts;
  d.kinetic_energy = of_spheres.kinetic_energy;
  d.max_speed = of_spheres.max_speed;
  d.rms_speed = of_spheres.rms_speed;
  d.max_net_force = of_spheres.max_net_force;
  d.largest_surface_speed = of_spheres.largest_surface_speed;
  d.spheres_finite = of_spheres.finite;
  const Piston& piston = world.walls.piston;
  if (piston.enabled) {
    d.kinetic_energy += 0.5 * piston.mass * piston.velocity * piston.velocity;
    // against the push and the piston's weight: under gravity the spheres carry both
    const double load = piston_load(world);
    if (load > 0.0) d.piston_imbalance = std::abs(d.piston_contact_force - load) / load;
  }
  return d;
}

}  // namespace cdpowder
