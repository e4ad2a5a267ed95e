// integrate.cpp — velocity commit and position update, and the spheres' measures on the same
// pass, in lanes (integrate_lanes.inc, compiled for SSE2 and for AVX2 like the coloured kernel),
// in pieces of spheres fixed by their count on the step's threads. Each piece sums its spheres in
// index order and the pieces' sums are added in piece order, so the threads change no bit.
#include "cdpowder/solver/integrate.hpp"

#include "cdpowder/core/lanes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace cdpowder {

namespace {

/// What the pass reads and writes, through pointers held in locals: the stores into the World
/// could alias the vectors' own pointers and the box, which would then be reloaded for every
/// sphere.
struct IntegrateInputs {
  std::size_t n = 0;
  const std::uint8_t* fixed = nullptr;
  const double* radius = nullptr;
  const double* inverse_mass = nullptr;
  const double* inverse_inertia = nullptr;
  const SphereVelocity* next = nullptr;
  Vec3* velocity = nullptr;
  Vec3* angular_velocity = nullptr;
  Vec3* position = nullptr;
  PeriodicBox box;
  double dt = 0.0;
};

/// A piece's sums and maxima, from which SphereMeasures is formed; on cache lines of its own
/// (threads write them side by side).
struct alignas(64) SpherePassSums {
  double kinetic_energy = 0.0;
  double moving_mass = 0.0;
  double mass_v2 = 0.0;
  double largest_v2 = 0.0;
  double net_force = 0.0;
  double surface_speed = 0.0;
  bool finite = true;

  /// Adds the next piece's sums and maxima (max is exact; the sums are added in piece order).
  void merge(const SpherePassSums& other) {
    kinetic_energy += other.kinetic_energy;
    moving_mass += other.moving_mass;
    mass_v2 += other.mass_v2;
    largest_v2 = std::max(largest_v2, other.largest_v2);
    net_force = std::max(net_force, other.net_force);
    surface_speed = std::max(surface_speed, other.surface_speed);
    finite = finite && other.finite;
  }
};

}  // namespace

#define CDP_LANE_CODE "cdpowder/solver/integrate_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

SphereMeasures integrate(const VelocityCache& velocities, double dt, World& world,
                         PieceRunner* pieces) {
  Bodies& bodies = world.bodies;
  IntegrateInputs in;
  in.n = bodies.size();
  in.fixed = bodies.fixed.data();
  in.radius = bodies.radius.data();
  in.inverse_mass = bodies.inverse_mass.data();
  in.inverse_inertia = bodies.inverse_inertia.data();
  in.next = velocities.spheres.data();
  in.velocity = bodies.velocity.data();
  in.angular_velocity = bodies.angular_velocity.data();
  in.position = bodies.position.data();
  in.box = world.box;
  in.dt = dt;
  // pieces of whole blocks of lanes, fixed by the count (indices_per_piece)
  const auto sums = run_summed_pieces<SpherePassSums>(
      pieces, in.n, [&](std::size_t first, std::size_t last, SpherePassSums& out) {
        CDP_LANES_FOR_CPU(integrate_spheres)(in, first, last, out);
      });

  Piston& piston = world.walls.piston;
  if (piston.enabled) {
    piston.velocity = velocities.piston_velocity;
    piston.height += dt * piston.velocity;
  }
  world.time += dt;
  ++world.step;

  SphereMeasures m;
  m.kinetic_energy = sums.kinetic_energy;
  // √ rounds monotonically, so √(max |v|²) is the largest √|v|², bit for bit
  m.max_speed = std::max(0.0, std::sqrt(sums.largest_v2));
  m.rms_speed = sums.moving_mass > 0.0 ? std::sqrt(sums.mass_v2 / sums.moving_mass) : 0.0;
  m.max_net_force = sums.net_force;
  m.largest_surface_speed = sums.surface_speed;
  m.finite = sums.finite;
  return m;
}

}  // namespace cdpowder
