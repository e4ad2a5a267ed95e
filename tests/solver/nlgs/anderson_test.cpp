// anderson_test.cpp — Anderson acceleration on linear fixed-point maps with known solutions.
//
// For an affine map G(x) = A x + b, type-II Anderson mixing with depth ≥ n is a Krylov
// method and reaches the fixed point x* = (I − A)⁻¹ b in about n + 1 iterations; with a
// smaller depth (the ring buffer wraps) it must still beat plain iteration by far.
#include "cdpowder/solver/nlgs/anderson.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cdpowder {
namespace {

struct AffineMap {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;

  Eigen::VectorXd solution() const {
    const auto n = a.rows();
    return (Eigen::MatrixXd::Identity(n, n) - a).lu().solve(b);
  }
};

/// A symmetric map with spectrum in [0, rho_max]: plain iteration contracts by rho_max.
AffineMap slow_map(int n, double rho_max) {
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) q(i, j) = std::sin(1.0 + i * 7.0 + j * 3.0 + i * j);
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(q);
  const Eigen::MatrixXd orthogonal = qr.householderQ();
  Eigen::VectorXd eig(n);
  for (int i = 0; i < n; ++i) eig(i) = rho_max * (i + 1.0) / n;
  AffineMap m;
  m.a = orthogonal * eig.asDiagonal() * orthogonal.transpose();
  m.b = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  return m;
}

/// Iterations of x ← AA(G) until |x − x*| < tol·|x*|, or -1 after max_iterations.
int iterations_to(const AffineMap& map, AndersonAccelerator* accelerator, double tol,
                  int max_iterations) {
  const auto n = static_cast<std::size_t>(map.b.size());
  const Eigen::VectorXd exact = map.solution();
  AlignedVector<double> x(n, 0.0), g(n), next(n);
  for (int it = 1; it <= max_iterations; ++it) {
    const Eigen::Map<const Eigen::VectorXd> xv(x.data(), map.b.size());
    Eigen::Map<Eigen::VectorXd>(g.data(), map.b.size()) = map.a * xv + map.b;
    if (accelerator != nullptr) {
      accelerator->extrapolate(x, g, next);
      x.swap(next);
    } else {
      x = g;
    }
    const Eigen::Map<const Eigen::VectorXd> now(x.data(), map.b.size());
    if ((now - exact).norm() < tol * exact.norm()) return it;
  }
  return -1;
}

TEST(Anderson, FullDepthSolvesAnAffineMapInAboutNPlusOneIterations) {
  const AffineMap map = slow_map(6, 0.99);
  AndersonAccelerator accelerator(8);
  const int accelerated = iterations_to(map, &accelerator, 1e-9, 100);
  EXPECT_GT(accelerated, 0);
  EXPECT_LE(accelerated, 6 + 3);
  // plain iteration contracts by 0.99 per step: ~2000 iterations to 1e-9
  EXPECT_EQ(iterations_to(map, nullptr, 1e-9, 500), -1);
}

// Depths from 11 on mix more slots than the mixing loops are unrolled for (anderson.cpp):
// the generic loops must give the same Krylov behaviour.
TEST(Anderson, DeepRingsBeyondTheUnrolledCountsSolveAnAffineMap) {
  for (const int depth : {12, 16}) {
    const AffineMap map = slow_map(depth - 2, 0.99);
    AndersonAccelerator accelerator(depth);
    const int accelerated = iterations_to(map, &accelerator, 1e-9, 100);
    EXPECT_GT(accelerated, 0) << depth;
    EXPECT_LE(accelerated, depth - 2 + 3) << depth;
  }
}

TEST(Anderson, ShortRingStillAcceleratesAfterWrappingAround) {
  const AffineMap map = slow_map(40, 0.99);
  AndersonAccelerator accelerator(3);  // the ring wraps many times
  const int accelerated = iterations_to(map, &accelerator, 1e-8, 400);
  EXPECT_GT(accelerated, 0);
  EXPECT_EQ(iterations_to(map, nullptr, 1e-8, 400), -1);
}

// ΔF is stored in single precision (anderson.hpp): the fit's weights are a little off, but
// the mixed iterate stays an exact affine combination of the map's outputs, so the iteration
// converges to the last bits of double precision rather than to a floor of about 1e-7.
TEST(Anderson, SinglePrecisionDifferencesStillReachADoublePrecisionFixedPoint) {
  const AffineMap map = slow_map(40, 0.99);
  AndersonAccelerator accelerator(5);
  const int accelerated = iterations_to(map, &accelerator, 1e-14, 400);
  EXPECT_GT(accelerated, 0);
  EXPECT_EQ(iterations_to(map, nullptr, 1e-14, 400), -1);
}

TEST(Anderson, ResetForgetsHistoryAndAFreshStartMatchesANewAccelerator) {
  const AffineMap map = slow_map(10, 0.95);
  AndersonAccelerator reused(4);
  iterations_to(map, &reused, 1e-9, 7);  // leaves history behind
  reused.reset();
  EXPECT_EQ(reused.history(), 0);
  AndersonAccelerator fresh(4);
  EXPECT_EQ(iterations_to(map, &reused, 1e-10, 200), iterations_to(map, &fresh, 1e-10, 200));
}

TEST(Anderson, FirstCallHasNoHistoryAndReturnsTheSweptIterate) {
  AndersonAccelerator accelerator(5);
  const AlignedVector<double> x{1.0, 2.0};
  const AlignedVector<double> g{0.5, 1.5};
  AlignedVector<double> next;
  EXPECT_FALSE(accelerator.extrapolate(x, g, next));
  EXPECT_EQ(next, g);
  EXPECT_EQ(accelerator.history(), 0);
}

TEST(Anderson, DepthIsClampedAndAChangedSizeStartsOver) {
  EXPECT_EQ(AndersonAccelerator(0).depth(), 1);
  EXPECT_EQ(AndersonAccelerator(100).depth(), AndersonAccelerator::kMaxDepth);
  AndersonAccelerator accelerator(3);
  AlignedVector<double> next;
  accelerator.extrapolate({1.0, 2.0}, {0.5, 1.0}, next);
  accelerator.extrapolate({0.5, 1.0}, {0.3, 0.6}, next);
  EXPECT_EQ(accelerator.history(), 1);
  EXPECT_FALSE(accelerator.extrapolate({1.0, 2.0, 3.0}, {0.5, 1.0, 1.5}, next));
  EXPECT_EQ(accelerator.history(), 0);
}

/// One mixing by the stages of a tiled step (begin, pass over `pass_cuts`' ranges, fit with
/// their sums added in range order, mix over `mix_cuts`' ranges): the accelerator's mixed
/// iterate in `next`, or g when the fit has nothing yet. Cuts are the ranges' ends.
bool mix_in_ranges(AndersonAccelerator& accelerator, const AlignedVector<double>& x,
                   const AlignedVector<double>& g, const std::vector<std::size_t>& pass_cuts,
                   const std::vector<std::size_t>& mix_cuts, AlignedVector<double>& next) {
  accelerator.begin(g.size());
  std::copy(g.begin(), g.end(), accelerator.output());
  std::vector<AndersonAccelerator::PassSums> sums;
  std::size_t first = 0;
  for (const std::size_t last : pass_cuts) {
    sums.push_back(accelerator.pass(x.data(), first, last));
    first = last;
  }
  next.assign(g.begin(), g.end());
  if (!accelerator.fit(sums)) return false;
  first = 0;
  for (const std::size_t last : mix_cuts) {
    accelerator.mix(next.data(), first, last);
    first = last;
  }
  return true;
}

// The stages of a tiled step's mixing (tile_solve.hpp) against extrapolate(), fed the same
// iterates of an affine map: over one range the same bits; over three ranges whose sums are
// added in order, and mixed over other ranges, the same iterate to rounding (the ranges' sums
// round apart), every iteration, with the ring wrapped several times.
TEST(Anderson, TheStagesOverRangesMixAsExtrapolateDoes) {
  const AffineMap map = slow_map(300, 0.98);
  const auto n = static_cast<std::size_t>(map.b.size());
  AndersonAccelerator whole(5);
  AndersonAccelerator one_range(5);
  AndersonAccelerator ranges(5);
  AlignedVector<double> x(n, 0.0);
  AlignedVector<double> g(n);
  AlignedVector<double> by_whole;
  AlignedVector<double> by_one;
  AlignedVector<double> by_ranges;
  int mixed = 0;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Map<const Eigen::VectorXd> xv(x.data(), map.b.size());
    Eigen::Map<Eigen::VectorXd>(g.data(), map.b.size()) = map.a * xv + map.b;
    const bool w = whole.extrapolate(x, g, by_whole);
    const bool o = mix_in_ranges(one_range, x, g, {n}, {n}, by_one);
    const bool r = mix_in_ranges(ranges, x, g, {76, 200, n}, {4, 150, n}, by_ranges);
    ASSERT_EQ(w, o) << "iteration " << it;
    ASSERT_EQ(w, r) << "iteration " << it;
    mixed += w ? 1 : 0;
    EXPECT_EQ(by_one, by_whole) << "iteration " << it;
    double largest = 0.0;
    double norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      largest = std::max(largest, std::abs(by_ranges[i] - by_whole[i]));
      norm = std::max(norm, std::abs(by_whole[i]));
    }
    EXPECT_LE(largest, 1e-12 * norm) << "iteration " << it;
    x = by_whole;
  }
  EXPECT_GE(mixed, 25);
}

/// The solver's loop (nlgs.cpp, mix_actions): the next pass starts from `start` after a mixing
/// that was adopted and from the accelerator's last output otherwise; every `restart`-th
/// iteration forgets the history, as the restart rule does. `copy_x` hands the accelerator a
/// copy of x instead of x where it lies. Returns the iterates the passes started from; counts in
/// `in_place_passes` the passes with a history that started from the last output (pass 1's
/// kernel, which reads x from the array it writes the new last output to).
std::vector<AlignedVector<double>> solver_iterates(const AffineMap& map, bool copy_x, int restart,
                                                   int& in_place_passes) {
  const auto n = static_cast<std::size_t>(map.b.size());
  AndersonAccelerator accelerator(3);
  AlignedVector<double> start(n, 0.0);
  AlignedVector<double> copy(n);
  bool from_output = false;
  std::vector<AlignedVector<double>> iterates;
  for (int it = 1; it <= 40; ++it) {
    if (it % restart == 0) accelerator.reset();
    const double* x = from_output ? accelerator.last_output() : start.data();
    iterates.emplace_back(x, x + n);
    if (copy_x) {
      std::copy(x, x + n, copy.begin());
      x = copy.data();
    }
    accelerator.begin(n);
    if (from_output && accelerator.history() > 0) ++in_place_passes;
    const Eigen::Map<const Eigen::VectorXd> xv(x, map.b.size());
    Eigen::Map<Eigen::VectorXd>(accelerator.output(), map.b.size()) = map.a * xv + map.b;
    from_output = !accelerator.extrapolate(x, start.data());
  }
  return iterates;
}

// A pass that starts from the accelerator's last output reads it where it lies, while the same
// pass writes the new last output over it entry by entry (anderson_lanes.inc): the same bits
// as from a copy, through restarts (a first pass after a reset, and the pass after it) and the
// ring's wrap-around.
TEST(Anderson, APassFromTheLastOutputInPlaceGivesTheBitsOfACopy) {
  const AffineMap map = slow_map(301, 0.98);  // n mod 4 = 1: the scalar tail too
  for (const int restart : {5, 7, 1000}) {
    int in_place_passes = 0;
    int copied_passes = 0;
    const std::vector<AlignedVector<double>> in_place =
        solver_iterates(map, false, restart, in_place_passes);
    const std::vector<AlignedVector<double>> copied =
        solver_iterates(map, true, restart, copied_passes);
    EXPECT_GE(in_place_passes, 1) << "restart " << restart;  // the aliased path ran
    ASSERT_EQ(in_place.size(), copied.size());
    for (std::size_t it = 0; it < in_place.size(); ++it) {
      EXPECT_EQ(in_place[it], copied[it]) << "restart " << restart << ", iteration " << it;
    }
  }
}

}  // namespace
}  // namespace cdpowder
