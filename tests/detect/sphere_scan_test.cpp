// Tests for src/cdpowder/detect/sphere_scan.cpp: the passes over the spheres in lanes give
// the scalar loops' results, bit for bit, on every instruction set, for every count of
// spheres modulo the lanes, with NaN, ties and periodic images where the scalar tests meet
// them. (The passes are compiled for SSE2 and AVX2; an AVX-512 CPU runs the AVX2 copy.)
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

/// The instruction sets this CPU has, the widest last (each test puts the default back with a
/// RestoreIsa).
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
        const auto last = static_cast<std::size_t>(n);
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

/// The definition: no sphere of [first, last) farther than √slack_sq from its anchor, the
/// minimum image in x and y, none in z.
bool scalar_within(const std::vector<Vec3>& position, const std::vector<Vec3>& anchor,
                   const PeriodicBox& box, double slack_sq, std::size_t first, std::size_t last) {
  for (std::size_t i = first; i < last; ++i) {
    if (box.minimum_image(position[i] - anchor[i]).squaredNorm() > slack_sq) return false;
  }
  return true;
}

TEST(SphereScan, AllWithinGivesTheScalarTestsAnswerOnEveryInstructionSet) {
  const RestoreIsa restore;
  const PeriodicBox box{10.0, 7.0};  // not square: x and y each with their own length
  for (const lanes::Isa isa : isas()) {
    lanes::allow_isa(isa);
    for (const int n : {1, 2, 3, 7, 8, 9, 16, 17, 40}) {
      SCOPED_TRACE(::testing::Message() << n << " spheres, isa " << static_cast<int>(isa));
      const Bodies bodies = random_spheres(n, 5);
      const std::vector<Vec3> anchor = bodies.position;
      std::vector<Vec3> position = bodies.position;
      // each sphere a little off its anchor, some through the periodic boundary in x or y
      Rng rng = make_rng(6, RngStream::Deposition);
      for (int i = 0; i < n; ++i) {
        Vec3& p = position[i];
        p += 0.1 * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
        if (i % 2 == 0) p.x() += p.x() < 5.0 ? 10.0 : -10.0;
        if (i % 3 == 0) p.y() += p.y() < 3.5 ? 7.0 : -7.0;
      }
      const auto count = static_cast<std::size_t>(n);
      const auto check = [&](const std::vector<Vec3>& at, double slack_sq, std::size_t first) {
        EXPECT_EQ(all_within(at.data(), anchor.data(), box, slack_sq, first, count),
                  scalar_within(at, anchor, box, slack_sq, first, count))
            << "slack² " << slack_sq << " from sphere " << first;
      };
      // every sphere's own d² as the slack², and the double just below it: ties within, the
      // sphere beyond by one unit in the last place
      for (int i = 0; i < n; ++i) {
        const double d2 = box.minimum_image(position[i] - anchor[i]).squaredNorm();
        for (const double slack_sq : {d2, std::nextafter(d2, 0.0)}) {
          check(position, slack_sq, 0);
          check(position, slack_sq, static_cast<std::size_t>(i));
        }
      }
      // one sphere moved beyond, or to NaN, in turn: in a full block or the partial one
      for (int moved = 0; moved < n; ++moved) {
        std::vector<Vec3> one = position;
        one[moved].z() += 6.0;  // past half a period, but z is not periodic
        check(one, 0.01, 0);
        check(one, 0.01, static_cast<std::size_t>(moved) + 1);  // outside [first, last)
        one[moved].z() = kNaN;                                  // a NaN distance is within
        check(one, 0.01, 0);
      }
    }
  }
}

}  // namespace
}  // namespace cdpowder
