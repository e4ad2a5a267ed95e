// detect_contacts.cpp — candidate pairs from the cell grid, sphere–wall candidates,
// and the start-of-step geometry that stays frozen during the sweeps (physics.md §3).
#include "cdpowder/detect/detect_contacts.hpp"

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/model/finite.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

double candidate_gap(const World& world, const DetectionSettings& settings) {
  const Bodies& bodies = world.bodies;
  double v_max = 0.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double surface_speed =
        bodies.velocity[i].norm() + bodies.radius[i] * bodies.angular_velocity[i].norm();
    v_max = std::max(v_max, surface_speed);
  }
  if (world.walls.piston.enabled) v_max = std::max(v_max, std::abs(world.walls.piston.velocity));
  return std::max(settings.cohesion_range, 2.0 * v_max * settings.dt) + settings.skin;
}

void detect_contacts(World& world, const DetectionSettings& settings, CellGrid& grid,
                     Contacts& contacts, CandidateList* reuse) {
  // stage 1 is the start of a step: its inputs must be finite (debug builds only)
  CDP_ASSERT(all_finite(world) && std::isfinite(settings.dt), "non-finite step input");
  Bodies& bodies = world.bodies;
  const PeriodicBox& box = world.box;
  for (Vec3& p : bodies.position) box.wrap(p);

  const double cutoff = candidate_gap(world, settings);
  contacts.clear();

  // sphere–sphere: centre distance < R_a + R_b + cutoff, among the pairs of the candidate
  // list (sorted by (a, b), the order of the warm-start cache), rebuilt when it no longer
  // covers this step's cutoff
  CandidateList fresh;
  CandidateList& list = reuse != nullptr ? *reuse : fresh;
  if (!list.covers(bodies, box, cutoff)) {
    list.rebuild(bodies, box, grid, cutoff, settings.verlet_margin);
  }
  for (const CandidateList::Pair& pair : list.pairs()) {
    const BodyIndex a = pair.a;
    const BodyIndex b = pair.b;
    const Vec3 d = box.minimum_image(bodies.position[b] - bodies.position[a]);
    const double reach = bodies.radius[a] + bodies.radius[b] + cutoff;
    const double distance_squared = d.squaredNorm();
    if (distance_squared >= reach * reach) continue;
    const double distance = std::sqrt(distance_squared);
    PairProblem p;
    p.a = a;
    p.b = b;
    // coincident centres have no normal; any unit vector keeps the kernel finite
    p.normal = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitZ();
    p.gap = distance - bodies.radius[a] - bodies.radius[b];
    // levers to the common contact point, the middle of the gap (physics.md §4.2)
    p.lever_a = bodies.radius[a] + 0.5 * p.gap;
    p.lever_b = bodies.radius[b] + 0.5 * p.gap;
    p.r_eff = effective_radius(bodies.radius[a], bodies.radius[b]);
    // the kernels assume a unit normal (d/|d| is one to a few ulp) and a finite gap
    CDP_ASSERT(std::abs(p.normal.norm() - 1.0) < 1e-12 && std::isfinite(p.gap), "n or g");
    contacts.pairs.push_back(p);
  }
  const auto sphere_count = static_cast<BodyIndex>(bodies.size());

  // sphere–wall, bottom first then piston, each in sphere order (the cache's key order)
  const auto add_wall = [&](WallKind kind, BodyIndex i, double gap, double normal_z) {
    WallProblem w;
    w.sphere = i;
    w.wall = kind;
    w.normal = Vec3(0.0, 0.0, normal_z);
    w.gap = gap;
    w.radius = bodies.radius[i];
    CDP_ASSERT(std::isfinite(gap), "non-finite wall gap");
    contacts.walls.push_back(w);
  };
  if (world.walls.bottom.enabled) {
    for (BodyIndex i = 0; i < sphere_count; ++i) {
      const double gap = bodies.position[i].z() - bodies.radius[i];
      if (gap < cutoff && bodies.fixed[i] == 0) add_wall(WallKind::Bottom, i, gap, 1.0);
    }
  }
  if (world.walls.piston.enabled) {
    const double z_piston = world.walls.piston.height;
    for (BodyIndex i = 0; i < sphere_count; ++i) {
      const double gap = z_piston - bodies.position[i].z() - bodies.radius[i];
      if (gap < cutoff) add_wall(WallKind::Piston, i, gap, -1.0);
    }
  }
}

}  // namespace cdpowder
