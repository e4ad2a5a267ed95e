// scene_setup.cpp — Scene → World.
#include "cdpowder/setup/scene_setup.hpp"

#include "cdpowder/config/particles_csv.hpp"
#include "cdpowder/setup/deposition.hpp"

#include <algorithm>
#include <utility>

namespace cdpowder {

namespace {

/// The cell, gravity, walls and piston of `scene` around the spheres `world` holds.
void place_walls(const Scene& scene, World& world) {
  world.box = PeriodicBox{scene.system.lx, scene.system.ly};
  world.gravity = scene.system.gravity;
  world.walls.bottom.enabled = scene.system.bottom_wall;
  check_box_fits(scene, world.bodies);

  Piston& piston = world.walls.piston;
  piston.enabled = scene.piston.enabled;
  if (piston.enabled) {
    piston.mass = scene.piston.mass;
    piston.force = scene.piston.push(world.box.area());
    piston.velocity = scene.piston.velocity;
    double top = 0.0;
    for (std::size_t i = 0; i < world.bodies.size(); ++i) {
      top = std::max(top, world.bodies.position[i].z() + world.bodies.radius[i]);
    }
    piston.height = scene.piston.height.value_or(top + scene.piston.start_gap);
  }
}

}  // namespace

World make_world(const Scene& scene, const StopRequest& stop_requested) {
  World world;
  if (scene.deposition) {
    deposit_ballistically(*scene.deposition, scene.system.density, world.bodies, stop_requested);
  } else {
    read_particles_csv(scene.particles_file, scene.system.density, world.bodies);
  }
  place_walls(scene, world);
  return world;
}

World make_world(const Scene& scene, Bodies spheres) {
  World world;
  world.bodies = std::move(spheres);
  place_walls(scene, world);
  return world;
}

}  // namespace cdpowder
