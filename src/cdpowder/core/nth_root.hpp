// nth_root.hpp — x^(1/n) for n = 1 … 8 from IEEE-754 operations alone, so that its bits are
// the same on every machine. The C library's pow is not: glibc 2.36 picks an FMA or an SSE2
// path by CPU, and 6 in 10 000 of its results for these exponents differ by one unit in the
// last place between the two (docs/lab/2026-11-28-detection-rebuild-and-nth-root.md); another
// library version may round differently again. The solver's contraction estimate feeds its
// stopping rule (nlgs.cpp), so it takes this root instead.
#pragma once

#include "cdpowder/core/assert.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace cdpowder {

inline constexpr int kMaxRootDegree = 8;

namespace detail {

/// 2^(r/n) for 0 ≤ r < n ≤ 8, each correctly rounded (computed to 60 digits offline).
/// 2^(1/2) is std::numbers::sqrt2 to the bit; the table spells every entry alike.
// NOLINTBEGIN(modernize-use-std-numbers)
inline constexpr std::array<std::array<double, kMaxRootDegree>, kMaxRootDegree + 1> kTwoToThe = {{
    {},
    {0x1.0000000000000p+0},
    {0x1.0000000000000p+0, 0x1.6a09e667f3bcdp+0},
    {0x1.0000000000000p+0, 0x1.428a2f98d728bp+0, 0x1.965fea53d6e3dp+0},
    {0x1.0000000000000p+0, 0x1.306fe0a31b715p+0, 0x1.6a09e667f3bcdp+0, 0x1.ae89f995ad3adp+0},
    {0x1.0000000000000p+0, 0x1.2611186bae675p+0, 0x1.51cb453b9536cp+0, 0x1.8406003b2ae5cp+0,
     0x1.bdb8cdadbe120p+0},
    {0x1.0000000000000p+0, 0x1.1f59ac3c7d6c0p+0, 0x1.428a2f98d728bp+0, 0x1.6a09e667f3bcdp+0,
     0x1.965fea53d6e3dp+0, 0x1.c823e074ec129p+0},
    {0x1.0000000000000p+0, 0x1.1aa59c4115e7dp+0, 0x1.381147622f886p+0, 0x1.588cea3f093bep+0,
     0x1.7c6a1f29e2ce6p+0, 0x1.a402feeb9c533p+0, 0x1.cfbb031a741a5p+0},
    {0x1.0000000000000p+0, 0x1.172b83c7d517bp+0, 0x1.306fe0a31b715p+0, 0x1.4bfdad5362a27p+0,
     0x1.6a09e667f3bcdp+0, 0x1.8ace5422aa0dbp+0, 0x1.ae89f995ad3adp+0, 0x1.d5818dcfba487p+0},
}};
// NOLINTEND(modernize-use-std-numbers)

/// Newton steps from 1 for m^(1/n), m in [1, 2): the first lands above the root (in
/// [1, 1.125) at n = 8, [1, 1.5) at n = 2) and the rest converge from there quadratically, to
/// within rounding after five (about 2 units in the last place at worst). The count is fixed,
/// not a test of convergence: in floating point the iterate may keep flipping by a unit, and a
/// fixed count is what makes the bits the same everywhere.
inline constexpr int kNewtonSteps = 6;

}  // namespace detail

/// x^(1/n) for 1 ≤ n ≤ kMaxRootDegree and x ≥ 0, within a few units in the last place of the
/// exact root and the same bits wherever IEEE-754 double arithmetic is (no FMA contraction: the
/// build's -ffp-contract=off). +0 for ±0 and +∞ for +∞, as pow gives them; NaN for NaN and for
/// any x < 0 (pow(x, 1.0) would give x: this root is not defined there).
inline double nth_root(double x, int n) {
  CDP_ASSERT(n >= 1 && n <= kMaxRootDegree, "root degree outside 1 … 8");
  if (x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 0.0;  // +0 for −0 too
  if (n == 1 || std::isnan(x) || std::isinf(x)) return x;
  // x = m 2^e with m in [1, 2) (frexp and ldexp are exact); e = q n + r with 0 ≤ r < n, so
  // x^(1/n) = 2^q · 2^(r/n) · m^(1/n), and a power of two 2^(q n) has the root 2^q exactly
  int e = 0;
  const double m = 2.0 * std::frexp(x, &e);
  --e;
  int q = e / n;
  int r = e - q * n;
  if (r < 0) {
    r += n;
    --q;
  }
  // y ← y + (m / y^(n−1) − y) / n: the correction form, whose rounding is that of a small term
  double y = 1.0;
  for (int step = 0; step < detail::kNewtonSteps; ++step) {
    double power = 1.0;
    for (int j = 1; j < n; ++j) power *= y;
    y = y + (m / power - y) / n;
  }
  return std::ldexp(detail::kTwoToThe[static_cast<std::size_t>(n)][static_cast<std::size_t>(r)] * y,
                    q);
}

}  // namespace cdpowder
