// step_diagnostics.cpp — overlaps from the new positions (the pairs in lanes:
// overlap_lanes.inc, in pieces), the piston balance, and the spheres' measures joined in.
#include "cdpowder/analysis/step_diagnostics.hpp"

#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/core/lanes.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdpowder {

namespace {

/// What the pairs' pass reads, through pointers held in locals.
struct PairOverlapInputs {
  std::size_t n = 0;  ///< pairs
  const PairProblem* pairs = nullptr;
  const ContactAction* actions = nullptr;
  const std::uint8_t* cohesive = nullptr;
  const Vec3* position = nullptr;
  const double* radius = nullptr;
  PeriodicBox box;
};

/// measure_contacts' running maxima, sums and counts of a piece, on cache lines of its own
/// (threads write them side by side).
struct alignas(64) ContactSums {
  double max_overlap = 0.0;
  double overlap_sum = 0.0;  ///< of the closed contacts
  double piston_force = 0.0;
  std::size_t closed = 0;
  std::size_t cohesive = 0;

  /// Adds the next piece's maxima, sums and counts (the sums in piece order).
  void merge(const ContactSums& other) {
    max_overlap = std::max(max_overlap, other.max_overlap);
    overlap_sum += other.overlap_sum;
    piston_force += other.piston_force;
    closed += other.closed;
    cohesive += other.cohesive;
  }
};

/// What the pairs' lanes read of `world` and `contacts`.
PairOverlapInputs overlap_inputs(const World& world, const Contacts& contacts) {
  return {.n = contacts.pairs.size(),
          .pairs = contacts.pairs.data(),
          .actions = contacts.pair_actions.data(),
          .cohesive = contacts.pair_cohesive.data(),
          .position = world.bodies.position.data(),
          .radius = world.bodies.radius.data(),
          .box = world.box};
}

/// A contact's overlap from the new positions (c.gap is the step's start), as the pairs'
/// lanes compute it for a pair.
double overlap_after_step(const World& world, const ContactView& c) {
  const Bodies& bodies = world.bodies;
  if (!c.wall) {  // a pair (ContactView::is_pair)
    const Vec3 d_ab = world.box.minimum_image(bodies.position[c.b] - bodies.position[c.a]);
    return std::max(0.0, bodies.radius[c.a] + bodies.radius[c.b] - d_ab.norm());
  }
  // detect_contacts gives a wall contact its sphere's radius
  const double z = bodies.position[c.b].z();
  const double r = bodies.radius[c.b];
  const double gap = c.wall == WallKind::Bottom ? z - r : world.walls.piston.height - z - r;
  return std::max(0.0, -gap);
}

}  // namespace

#define CDP_LANE_CODE "cdpowder/analysis/overlap_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

void measure_contacts(const World& world, const Contacts& contacts, StepDiagnostics& d,
                      PieceRunner* pieces) {
  d.contacts = contacts.size();
  const auto measure = [&](const ContactView& c, ContactSums& sums) {
    const double overlap = overlap_after_step(world, c);
    sums.max_overlap = std::max(sums.max_overlap, overlap);
    if (c.cohesive) ++sums.cohesive;
    if (c.closed()) {
      ++sums.closed;
      sums.overlap_sum += overlap;
    }
    // n = −e_z at the piston: the force on the piston is −R, its z part +R_n
    if (c.wall == WallKind::Piston) sums.piston_force += c.action->normal_force;
  };
  // the pairs in pieces, each in blocks of lanes and its last partial block one by one; then
  // the walls on the caller
  const PairOverlapInputs lanes_in = overlap_inputs(world, contacts);
  auto sums = run_summed_pieces<ContactSums>(
      pieces, lanes_in.n, [&](std::size_t first, std::size_t last, ContactSums& out) {
        const std::size_t rest = CDP_LANES_FOR_CPU(pair_overlap_lanes)(lanes_in, first, last, out);
        for_each_contact_in(contacts, rest, last, [&](const ContactView& c) { measure(c, out); });
      });
  for_each_contact_in(contacts, lanes_in.n, contacts.size(),
                      [&](const ContactView& c) { measure(c, sums); });
  d.max_overlap = std::max(d.max_overlap, sums.max_overlap);
  d.cohesive_contacts += sums.cohesive;
  d.closed_contacts += sums.closed;
  d.piston_contact_force += sums.piston_force;
  d.mean_overlap =
      d.closed_contacts > 0 ? sums.overlap_sum / static_cast<double>(d.closed_contacts) : 0.0;
}

std::vector<double> contact_overlaps(const World& world, const Contacts& contacts) {
  std::vector<double> overlaps(contacts.size(), 0.0);
  const PairOverlapInputs lanes_in = overlap_inputs(world, contacts);
  const std::size_t rest = CDP_LANES_FOR_CPU(pair_overlaps_lanes)(lanes_in, overlaps.data());
  std::size_t k = rest;
  for_each_contact_in(contacts, rest, contacts.size(),
                      [&](const ContactView& c) { overlaps[k++] = overlap_after_step(world, c); });
  return overlaps;
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
