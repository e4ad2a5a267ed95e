// Tests for src/cdpowder/detect/sphere_scan.cpp: the passes over the spheres in lanes give
// the scalar loops' results, bit for bit, on every instruction set, for every count of
// spheres modulo the lanes, with NaN and periodic images where the scalar tests meet them.
#include "cdpowder/detect/sphere_scan.hpp"

#include "cdpowder/core/lanes.hpp"
#include "cdpowder/core/rng.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdpowder {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The instruction sets this CPU has, the widest last (lanes::allow_isa restores the default
/// after the loop: see Restore below).
std::vector<lanes::Isa> isas() {
  std::vector<lanes::Isa> out;
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2, lanes::Isa::Avx512}) {
    if (lanes::allow_isa(isa)) out.push_back(isa);
  }
  return out;
}

struct RestoreIsa {
  ~RestoreIsa() { lanes::allow_isa(lanes::Isa::Avx512); }
};

Bodies random_spheres(int n, std::uint64_t seed) {
  Rng rng = make_rng(seed, RngStream::Deposition);
  Bodies bodies;
  for (int i = 0; i < n; ++i) {
    const BodyIndex k =
        bodies.add_sphere(Vec3(10.0 * uniform01(rng), 10.0 * uniform01(rng), 10.0 * uniform01(rng)),
                          0.5 + uniform01(rng), 1.0);
    bodies.velocity[k] = Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
    bodies.angular_velocity[k] =
        Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
  }
  return bodies;
}

/// The definition: std::max over the spheres from 0, one scalar expression each.
double scalar_speed(const Bodies& bodies, std::size_t first, std::size_t last) {
  double v_max = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    v_max = std::max(
        v_max, bodies.velocity[i].norm() + bodies.radius[i] * bodies.angular_velocity[i].norm());
  }
  return v_max;
}

TEST(SphereScan, LargestSurfaceSpeedHasTheScalarLoopsBitsOnEveryInstructionSet) {
  const RestoreIsa restore;
  for (const lanes::Isa isa : isas()) {
    lanes::allow_isa(isa);
    for (const int n : {0, 1, 2, 3, 5, 8, 9, 17, 40, 151}) {
      Bodies bodies = random_spheres(n, 3);
      // the fastest sphere in the last, partial block or in a full one, and a NaN speed,
      // which both pass over
      if (n >= 9) bodies.velocity[n - 1] *= 40.0;
      if (n >= 17) bodies.angular_velocity[4] = Vec3(kNaN, 0.0, 0.0);
      for (const std::size_t first : {std::size_t{0}, std::size_t{1}}) {
        const std::size_t last = static_cast<std::size_t>(n);
        if (first > last) continue;
        SCOPED_TRACE(::testing::Message()
                     << n << " spheres from " << first << ", isa " << static_cast<int>(isa));
        const double lanes = largest_surface_speed(bodies, first, last);
        const double scalar = scalar_speed(bodies, first, last);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes), std::bit_cast<std::uint64_t>(scalar));
        EXPECT_FALSE(std::isnan(lanes));
      }
    }
  }
}

TEST(SphereScan, AllWithinMatchesTheScalarTestOnEveryInstructionSet) {
  const RestoreIsa restore;
  const PeriodicBox box{10.0, 10.0};
  for (const lanes::Isa isa : isas()) {
    lanes::allow_isa(isa);
    for (const int n : {1, 2, 3, 7, 8, 9, 16, 17, 40}) {
      const Bodies bodies = random_spheres(n, 5);
      std::vector<Vec3> anchor = bodies.position;
      std::vector<Vec3> position = bodies.position;
      // every sphere ≈ 0.09 from its anchor, the even ones through the periodic boundary in x
      for (int i = 0; i < n; ++i) {
        anchor[i].x() = i % 2 == 0 ? 0.02 : 5.0;
        position[i].x() = i % 2 == 0 ? 9.93 : 5.09;
      }
      const auto test = [&](double slack_sq, int moved) {
        return all_within(position.data(), anchor.data(), box, slack_sq, 0,
                          static_cast<std::size_t>(n)) == (moved < 0);
      };
      SCOPED_TRACE(::testing::Message() << n << " spheres, isa " << static_cast<int>(isa));
      EXPECT_TRUE(test(0.01, -1));          // 0.09² < 0.01
      EXPECT_TRUE(test(0.0081 * 0.99, 0));  // just below 0.09²: every sphere beyond
      // one sphere beyond in turn, in a full block or the partial one
      for (int moved = 0; moved < n; ++moved) {
        std::vector<Vec3> one = position;
        one[moved].z() += 0.5;
        EXPECT_FALSE(
            all_within(one.data(), anchor.data(), box, 0.01, 0, static_cast<std::size_t>(n)))
            << "sphere " << moved;
        // a NaN position is within, as in the scalar test
        one[moved].z() = kNaN;
        EXPECT_TRUE(
            all_within(one.data(), anchor.data(), box, 0.01, 0, static_cast<std::size_t>(n)))
            << "sphere " << moved;
        // outside [first, last) it is not looked at
        one[moved].z() = anchor[moved].z() + 3.0;
        EXPECT_TRUE(all_within(one.data(), anchor.data(), box, 0.01,
                               static_cast<std::size_t>(moved) + 1, static_cast<std::size_t>(n)));
      }
    }
  }
}

}  // namespace
}  // namespace cdpowder
