// tiny_world.cpp — the shared test scene builder.
#include "support/tiny_world.hpp"

namespace cdpowder::testing {

TinyScene::TinyScene(double lx, double ly) {
  world.box = PeriodicBox{lx, ly};
  settings.solver.tolerance = 1e-10;
  settings.solver.max_passes = 10000;
  settings.laws.spheres = ContactLaw{};
  settings.laws.walls = ContactLaw{};
}

BodyIndex TinyScene::add(const Vec3& centre, double r, bool fixed) {
  return world.bodies.add_sphere(centre, r, 1.0, fixed);
}

StepReport TinyScene::run(int steps) {
  StepReport report;
  for (int s = 0; s < steps; ++s) report = step(world, work, settings);
  return report;
}

ContactAction TinyScene::pair_action(BodyIndex a, BodyIndex b) const {
  const Contacts& c = work.contacts;
  for (std::size_t k = 0; k < c.pairs.size(); ++k) {
    if (c.pairs[k].a == a && c.pairs[k].b == b) return c.pair_actions[k];
  }
  return {};
}

ContactAction TinyScene::wall_action(BodyIndex i, WallKind wall) const {
  const Contacts& c = work.contacts;
  for (std::size_t k = 0; k < c.walls.size(); ++k) {
    if (c.walls[k].sphere == i && c.walls[k].wall == wall) return c.wall_actions[k];
  }
  return {};
}

Vec3 total_momentum(const Bodies& bodies) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < bodies.size(); ++i) p += bodies.mass(i) * bodies.velocity[i];
  return p;
}

Vec3 total_angular_momentum(const Bodies& bodies) {
  Vec3 l = Vec3::Zero();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    l += bodies.position[i].cross(bodies.mass(i) * bodies.velocity[i]) +
         bodies.inertia(i) * bodies.angular_velocity[i];
  }
  return l;
}

}  // namespace cdpowder::testing
