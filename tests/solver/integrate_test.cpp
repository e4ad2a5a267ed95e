// Tests for src/cdpowder/solver/integrate.cpp: the step's commit, and the measures its pass
// over the spheres takes, each against a pass of its own written out here (the definitions
// of analysis/sphere_measures.hpp) to the last bit.
#include "cdpowder/solver/integrate.hpp"

#include "cdpowder/core/lanes.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace cdpowder {
namespace {

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

Vec3 random_vec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

/// `n` spheres of three radii in a 10 × 10 cell, every fifth fixed (1, 6, 11, …) (with a velocity
/// of its own, which integrate leaves), sphere 3 free but without mass (1/m = 1/I = 0: it moves and
/// carries no energy), random velocities before and after the step, some spheres about to
/// leave the cell. 41 spheres end in a partial block of lanes on every instruction set.
struct Scene {
  explicit Scene(int n = 41) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    world.box = PeriodicBox{10.0, 10.0};
    for (int i = 0; i < n; ++i) {
      const double r = 0.5 + 0.25 * (i % 3);
      const Vec3 centre(10.0 * unit(rng), i % 7 == 0 ? 9.999 : 10.0 * unit(rng),
                        1.0 + 5.0 * unit(rng));
      world.bodies.add_sphere(centre, r, 1.0, i % 5 == 1);
      world.bodies.velocity[i] = random_vec(rng, 0.3);
      world.bodies.angular_velocity[i] = random_vec(rng, 0.2);
    }
    if (n > 3) world.bodies.inverse_mass[3] = world.bodies.inverse_inertia[3] = 0.0;
    world.walls.piston.enabled = true;
    world.walls.piston.velocity = -0.01;
    world.walls.piston.height = 8.0;
    velocities.spheres.resize(world.bodies.size());
    for (std::size_t i = 0; i < world.bodies.size(); ++i) {
      SphereVelocity& s = velocities.spheres[i];
      if (world.bodies.fixed[i] != 0) continue;  // v* of a fixed sphere is zero
      s.linear = random_vec(rng, 0.3);
      s.angular = random_vec(rng, 0.2);
      s.dt_inverse_mass = kDt * world.bodies.inverse_mass[i];
      s.dt_inverse_inertia = kDt * world.bodies.inverse_inertia[i];
    }
    velocities.piston_velocity = -0.02;
  }

  static constexpr double kDt = 0.01;
  World world;
  VelocityCache velocities;
};

/// Each free sphere of `after` has its v* and moved by Δt v* from `before` (wrapped into the
/// cell); each fixed sphere kept its velocity and place.
void expect_committed(const World& before, const Scene& after) {
  for (std::size_t i = 0; i < before.bodies.size(); ++i) {
    if (before.bodies.fixed[i] != 0) {
      EXPECT_EQ(after.world.bodies.velocity[i], before.bodies.velocity[i]) << i;
      EXPECT_EQ(after.world.bodies.position[i], before.bodies.position[i]) << i;
      continue;
    }
    EXPECT_EQ(after.world.bodies.velocity[i], after.velocities.spheres[i].linear) << i;
    EXPECT_EQ(after.world.bodies.angular_velocity[i], after.velocities.spheres[i].angular) << i;
    Vec3 moved = before.bodies.position[i] + Scene::kDt * after.velocities.spheres[i].linear;
    before.box.wrap(moved);
    EXPECT_EQ(after.world.bodies.position[i], moved) << i;
    EXPECT_GE(after.world.bodies.position[i].y(), 0.0) << i;  // wrapped into the cell
    EXPECT_LT(after.world.bodies.position[i].y(), 10.0) << i;
  }
}

TEST(Integrate, CommitsTheVelocitiesAndMovesTheSpheres) {
  Scene s;
  const World before = s.world;
  (void)integrate(s.velocities, Scene::kDt, s.world);
  expect_committed(before, s);
  EXPECT_DOUBLE_EQ(s.world.walls.piston.height, 8.0 - 0.02 * Scene::kDt);
  EXPECT_EQ(s.world.walls.piston.velocity, -0.02);
  EXPECT_EQ(s.world.step, before.step + 1);
  EXPECT_DOUBLE_EQ(s.world.time, before.time + Scene::kDt);
}

/// integrate() on `s` against passes of their own over the World before and after it.
void expect_measures_of_passes_of_their_own(Scene& s) {
  const World before = s.world;
  const SphereMeasures m = integrate(s.velocities, Scene::kDt, s.world);
  const Bodies& old_bodies = before.bodies;
  const Bodies& bodies = s.world.bodies;

  // the spheres' speeds and energy on the World after the step, free spheres in index order,
  // summed piece by piece (indices_per_piece) and the pieces' sums in piece order
  const std::size_t per_piece = indices_per_piece(bodies.size());
  std::array<double, 3> sums{};   // kinetic energy, moving mass, Σ m v²
  std::array<double, 3> piece{};  // of the piece under way
  double max_speed = 0.0;
  double net_force = 0.0;
  double surface_speed = 0.0;
  const auto end_piece = [&] {
    for (std::size_t k = 0; k < sums.size(); ++k) sums[k] += piece[k];
    piece = {};
  };
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (i > 0 && i % per_piece == 0) end_piece();
    surface_speed =
        std::max(surface_speed,
                 bodies.velocity[i].norm() + bodies.radius[i] * bodies.angular_velocity[i].norm());
    if (bodies.fixed[i] != 0) continue;
    const double v2 = bodies.velocity[i].squaredNorm();
    max_speed = std::max(max_speed, std::sqrt(v2));
    piece[1] += bodies.mass(i);
    piece[2] += bodies.mass(i) * v2;
    piece[0] += 0.5 * bodies.mass(i) * v2 +
                0.5 * bodies.inertia(i) * bodies.angular_velocity[i].squaredNorm();
    // m|Δv|/Δt + I|Δω|/(Δt r), with Δt/m and Δt/I as the velocity cache holds them
    const SphereVelocity& next = s.velocities.spheres[i];
    if (next.dt_inverse_mass <= 0.0) continue;
    const double force = (next.linear - old_bodies.velocity[i]).norm() / next.dt_inverse_mass;
    const double torque = (next.angular - old_bodies.angular_velocity[i]).norm() /
                          next.dt_inverse_inertia / bodies.radius[i];
    net_force = std::max(net_force, force + torque);
  }
  end_piece();
  const auto [kinetic_energy, moving_mass, mass_v2] = sums;
  EXPECT_TRUE(same_bits(m.kinetic_energy, kinetic_energy));
  EXPECT_TRUE(same_bits(m.max_speed, max_speed));
  EXPECT_TRUE(same_bits(m.rms_speed, moving_mass > 0.0 ? std::sqrt(mass_v2 / moving_mass) : 0.0));
  EXPECT_TRUE(same_bits(m.max_net_force, net_force));
  EXPECT_TRUE(same_bits(m.largest_surface_speed, surface_speed));
  EXPECT_TRUE(m.finite);
}

TEST(Integrate, ItsMeasuresAreThoseOfPassesOfTheirOwnToTheLastBit) {
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    for (const int n : {1, 2, 3, 4, 5, 7, 40, 41}) {
      SCOPED_TRACE(::testing::Message() << n << " spheres, avx2 " << (isa == lanes::Isa::Avx2));
      Scene s(n);
      expect_measures_of_passes_of_their_own(s);
    }
    Scene s;
    const SphereMeasures m = integrate(s.velocities, Scene::kDt, s.world);
    EXPECT_GT(m.kinetic_energy, 0.0);
    EXPECT_GT(m.max_net_force, 0.0);
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

TEST(Integrate, NetForceIsTheMassTimesTheVelocityChangeOverTheStep) {
  World world;
  world.box = PeriodicBox{10.0, 10.0};
  world.bodies.add_sphere(Vec3(5.0, 5.0, 5.0), 1.0, 1.0);
  const double mass = world.bodies.mass(0);
  const double inertia = world.bodies.inertia(0);
  VelocityCache velocities;
  velocities.spheres.resize(1);
  SphereVelocity& s = velocities.spheres[0];
  s.dt_inverse_mass = 0.1 / mass;
  s.dt_inverse_inertia = 0.1 / inertia;
  s.linear = Vec3(0.0, 0.3, 0.4);   // |Δv| = 0.5 from rest in Δt = 0.1: F = 5 m
  s.angular = Vec3(0.2, 0.0, 0.0);  // |Δω| = 0.2: T / r = 2 I
  const SphereMeasures m = integrate(velocities, 0.1, world);
  EXPECT_NEAR(m.max_net_force, 5.0 * mass + 2.0 * inertia, 1e-12);
  EXPECT_NEAR(m.kinetic_energy, 0.5 * mass * 0.25 + 0.5 * inertia * 0.04, 1e-14);
  EXPECT_NEAR(m.largest_surface_speed, 0.5 + 0.2, 1e-15);
  EXPECT_NEAR(m.rms_speed, 0.5, 1e-15);
}

// More spheres than one piece holds (core/pieces.hpp, indices_per_piece): the pieces, one after
// the other or side by side on two threads, commit every sphere and give the measures of one
// pass, to the last bit.
TEST(Integrate, PiecesOnThreadsGiveTheBitsOfOnePass) {
  const int n = static_cast<int>(2 * kChunkIndices + 13);
  ASSERT_GT(chunks_of(n, indices_per_piece(n)), 2U);
  Scene serial(n);
  expect_measures_of_passes_of_their_own(serial);
  Scene one(n);
  Scene two(n);
  const World before = two.world;
  TileThreads threads(2);
  const SphereMeasures a = integrate(one.velocities, Scene::kDt, one.world);
  const SphereMeasures b = integrate(two.velocities, Scene::kDt, two.world, &threads);
  EXPECT_TRUE(same_bits(a.kinetic_energy, b.kinetic_energy));
  EXPECT_TRUE(same_bits(a.rms_speed, b.rms_speed));
  EXPECT_TRUE(same_bits(a.max_speed, b.max_speed));
  EXPECT_TRUE(same_bits(a.max_net_force, b.max_net_force));
  EXPECT_TRUE(same_bits(a.largest_surface_speed, b.largest_surface_speed));
  EXPECT_EQ(a.finite, b.finite);
  EXPECT_EQ(one.world.bodies.position, two.world.bodies.position);
  EXPECT_EQ(one.world.bodies.velocity, two.world.bodies.velocity);
  EXPECT_EQ(serial.world.bodies.position, two.world.bodies.position);
  expect_committed(before, two);  // every piece moved its spheres, the last partial one too
}

TEST(Integrate, ANonFiniteSphereIsFoundOnThePass) {
  const std::array<double, 3> bad_values{std::numeric_limits<double>::quiet_NaN(),
                                         std::numeric_limits<double>::infinity(),
                                         -std::numeric_limits<double>::infinity()};
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    for (const double bad : bad_values) {
      // sphere 13 in a whole block of lanes, sphere 40 alone in the last, partial one
      for (const std::size_t i : {std::size_t{13}, std::size_t{40}}) {
        for (int where = 0; where < 3; ++where) {
          Scene s;
          ASSERT_EQ(s.world.bodies.fixed[i], 0);
          if (where == 0) s.velocities.spheres[i].linear.y() = bad;
          if (where == 1) s.velocities.spheres[i].angular.z() = bad;
          if (where == 2) s.world.bodies.position[i].z() = bad;
          EXPECT_FALSE(integrate(s.velocities, Scene::kDt, s.world).finite)
              << bad << " " << i << " " << where;
        }
      }
    }
    // a fixed sphere's own velocity counts too
    Scene fixed;
    fixed.world.bodies.angular_velocity[1].x() = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(integrate(fixed.velocities, Scene::kDt, fixed.world).finite);
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

}  // namespace
}  // namespace cdpowder
