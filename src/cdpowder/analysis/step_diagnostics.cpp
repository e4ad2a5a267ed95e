// step_diagnostics.cpp — overlaps from the new positions, energies, piston balance.
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

void measure_spheres(const World& world, StepDiagnostics& d) {
  const Bodies& bodies = world.bodies;
  double moving_mass = 0.0;
  double mass_v2 = 0.0;
  // the sums in locals for the pass (a store to `d` would make every iteration reload the
  // vectors' pointers and redo mass(i)'s division); the largest |v|² and one square root:
  // √ rounds monotonically, so √(max |v|²) is the largest √|v|², bit for bit
  double kinetic_energy = d.kinetic_energy;
  double largest_v2 = 0.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies.fixed[i] != 0) continue;
    const double v2 = bodies.velocity[i].squaredNorm();
    largest_v2 = std::max(largest_v2, v2);
    const double mass = bodies.mass(i);
    moving_mass += mass;
    mass_v2 += mass * v2;
    kinetic_energy +=
        0.5 * mass * v2 + 0.5 * bodies.inertia(i) * bodies.angular_velocity[i].squaredNorm();
  }
  d.max_speed = std::max(d.max_speed, std::sqrt(largest_v2));
  d.kinetic_energy = kinetic_energy;
  d.rms_speed = moving_mass > 0.0 ? std::sqrt(mass_v2 / moving_mass) : 0.0;
}

StepDiagnostics join_measures(const World& world, const StepDiagnostics& of_contacts,
                              const StepDiagnostics& of_spheres) {
  StepDiagnostics d = of_contacts;
  d.kinetic_energy = of_spheres.kinetic_energy;
  d.max_speed = of_spheres.max_speed;
  d.rms_speed = of_spheres.rms_speed;
  const Piston& piston = world.walls.piston;
  if (piston.enabled) {
    d.kinetic_energy += 0.5 * piston.mass * piston.velocity * piston.velocity;
    // against the push and the piston's weight: under gravity the spheres carry both
    const double load = piston_load(world);
    if (load > 0.0) d.piston_imbalance = std::abs(d.piston_contact_force - load) / load;
  }
  return d;
}

double net_force_of_step(const Bodies& bodies, const VelocityCache& velocities) {
  double largest = 0.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const SphereVelocity& next = velocities.spheres[i];
    if (bodies.fixed[i] != 0 || next.dt_inverse_mass <= 0.0) continue;
    const double force = (next.linear - bodies.velocity[i]).norm() / next.dt_inverse_mass;
    const double torque = (next.angular - bodies.angular_velocity[i]).norm() /
                          next.dt_inverse_inertia / bodies.radius[i];
    largest = std::max(largest, force + torque);
  }
  return largest;
}

}  // namespace cdpowder
