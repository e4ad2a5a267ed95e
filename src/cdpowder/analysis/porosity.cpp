// porosity.cpp — grain volume, packing volume, porosity.
#include "cdpowder/analysis/porosity.hpp"

#include <algorithm>
#include <numbers>

namespace cdpowder {

double grain_volume(const Bodies& bodies) {
  double volume = 0.0;
  for (const double r : bodies.radius) volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return volume;
}

double packing_volume(const World& world) {
  double top = 0.0;
  if (world.walls.piston.enabled) {
    top = world.walls.piston.height;
  } else {
    for (std::size_t i = 0; i < world.bodies.size(); ++i) {
      top = std::max(top, world.bodies.position[i].z() + world.bodies.radius[i]);
    }
  }
  return world.box.area() * top;
}

double porosity(const World& world) {
  const double volume = packing_volume(world);
  return volume > 0.0 ? 1.0 - grain_volume(world.bodies) / volume : 0.0;
}

}  // namespace cdpowder
