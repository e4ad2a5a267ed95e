// Tests for src/cdpowder/core/nth_root.hpp: the root is within a few units in the last place
// of the exact one (its n-th power against x in the x87's wider significand), exact where the
// root is a power of two, gives pow's special values, and gives the bits pinned below: the
// promise is the same bits on every machine, so a change of the algorithm has to show up here.
#include "cdpowder/core/nth_root.hpp"

#include "cdpowder/core/rng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdpowder {
namespace {

static_assert(std::numeric_limits<long double>::digits > 53,
              "the reference power needs a significand wider than a double's");

/// How far y^n is from x, relative, with y^n in the x87's 64-bit significand: a root within
/// u units in the last place of the exact one gives about n u 2^-53.
double power_error(double y, int n, double x) {
  long double power = 1.0L;
  for (int j = 0; j < n; ++j) power *= static_cast<long double>(y);
  return static_cast<double>(std::fabs(power / static_cast<long double>(x) - 1.0L));
}

// Within 4 units in the last place of the exact root; the C library's pow(x, 1.0 / n) is not
// a reference for that, as 1.0 / n is not 1/n: at x ~ 2^-600 its cube root is ~35 units off.
TEST(NthRoot, IsWithinFourUnitsOfTheExactRootOverTheDoubles) {
  Rng rng = make_rng(7, RngStream::Deposition);
  for (int i = 0; i < 200000; ++i) {
    // x = m 2^e over the exponents of the normal doubles, the subnormals included
    const double x =
        std::ldexp(1.0 + uniform01(rng), -1073 + static_cast<int>(2097.0 * uniform01(rng)));
    const int n = 1 + i % kMaxRootDegree;
    ASSERT_LE(power_error(nth_root(x, n), n, x), n * 4.0 * 0x1p-53)
        << std::hexfloat << x << " ^ 1/" << n;
  }
}

TEST(NthRoot, PowersOfTwoHaveExactRoots) {
  for (int n = 1; n <= kMaxRootDegree; ++n) {
    for (const int k : {-130, -64, -3, 0, 1, 7, 120}) {
      EXPECT_EQ(nth_root(std::ldexp(1.0, k * n), n), std::ldexp(1.0, k)) << "2^" << k * n;
    }
  }
  EXPECT_EQ(nth_root(0.25, 2), 0.5);
  EXPECT_EQ(nth_root(0.3, 1), 0.3);
}

TEST(NthRoot, PassesTheSpecialValuesThrough) {
  const double inf = std::numeric_limits<double>::infinity();
  for (int n = 1; n <= kMaxRootDegree; ++n) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(nth_root(0.0, n)), std::bit_cast<std::uint64_t>(0.0));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(nth_root(-0.0, n)), std::bit_cast<std::uint64_t>(0.0));
    EXPECT_EQ(nth_root(inf, n), inf);
    EXPECT_TRUE(std::isnan(nth_root(std::numeric_limits<double>::quiet_NaN(), n)));
    EXPECT_TRUE(std::isnan(nth_root(-0.5, n)));
  }
}

// The bits of this implementation, pinned: subnormal, tiny, ordinary, near one and above one.
TEST(NthRoot, GivesThePinnedBits) {
  struct Case {
    double x;
    int n;
    double root;
  };

  const auto cases = std::to_array<Case>({
      {0x1.fc6b62b01ac52p-58, 3, 0x1.fecdbf2fb89efp-20},
      {0x1.fc6b62b01ac52p-58, 8, 0x1.d51829e7079ecp-8},
      {0x1.3333333333333p-2, 2, 0x1.186f174f88472p-1},
      {0x1.3333333333333p-2, 7, 0x1.af1852ac8937ap-1},
      {0x1.56e1fc2f8f359p-997, 5, 0x1.9b604aaaca625p-200},
      {0x1.ff7ced916872bp-1, 8, 0x1.ffef9bdc1ec17p-1},
      {0x1.b333333333333p+0, 3, 0x1.31881d4da7529p+0},
      {0x0.0000000000001p-1022, 5, 0x1.2611186bae675p-215},
  });
  for (const Case& c : cases) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(nth_root(c.x, c.n)),
              std::bit_cast<std::uint64_t>(c.root))
        << std::hexfloat << c.x << " ^ 1/" << c.n;
  }
}

}  // namespace
}  // namespace cdpowder
