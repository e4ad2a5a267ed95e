// anderson.cpp — the least-squares mixing of Anderson acceleration (type II).
#include "cdpowder/solver/nlgs/anderson.hpp"

#include "cdpowder/core/lanes.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cstring>
#include <type_traits>
#include <utility>

namespace cdpowder {

namespace {

/// Calls f(std::integral_constant<int, count>) for count < kUnrolled, so the loops below
/// keep their per-slot sums in registers and unroll over the slots; larger counts run the
/// generic loop (f(std::integral_constant<int, -1>)). The arithmetic, and its order for
/// every sum, is the same either way: results are bit-identical.
constexpr int kUnrolled = 10;

template <class F, int... I>
void dispatch_impl(int count, F&& f, std::integer_sequence<int, I...>) {
  const bool found = ((count == I ? (f(std::integral_constant<int, I>{}), true) : false) || ...);
  if (!found) f(std::integral_constant<int, -1>{});
}

template <class F>
void dispatch_by_count(int count, F&& f) {
  dispatch_impl(count, f, std::make_integer_sequence<int, kUnrolled>{});
}

/// The stored differences of the slots in a fit: ΔF's (single precision) and ΔG's.
using FSlotPointers = std::array<const float*, AndersonAccelerator::kMaxDepth>;
using GSlotPointers = std::array<const double*, AndersonAccelerator::kMaxDepth>;
using SlotWeights = std::array<double, AndersonAccelerator::kMaxDepth>;

/// The vectors pass 1 streams through: the iterate x, the last f and g (updated), the new
/// slot's differences (written, ΔF rounded to single precision; ΔG over the pass's output g,
/// which it holds until then); n values each. x may be last_g: every entry is read before
/// any is written.
struct PassOneVectors {
  const double* x;
  double* last_f;
  double* last_g;
  float* new_f;
  double* new_g;
  std::size_t n;
};

using PassOneSums = AndersonAccelerator::PassSums;

// The passes over the long vectors, compiled for SSE2 (the x86-64 baseline) and for AVX2
// (chosen at run time, lanes.hpp): a 4-double vector is two SSE2 registers or one AVX
// register, the same operations on the same operands, so the same bits.
#define CDP_LANE_CODE "cdpowder/solver/nlgs/anderson_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

}  // namespace

void AndersonAccelerator::set_depth(int depth) {
  depth_ = std::clamp(depth, 1, kMaxDepth);
  size_ = 0;  // the slot layout depends on the depth: lay out again on next use
  reset();
}

void AndersonAccelerator::reset() {
  has_last_ = false;
  count_ = 0;
  newest_ = 0;
}

bool AndersonAccelerator::extrapolate(const AlignedVector<double>& x,
                                      const AlignedVector<double>& g, AlignedVector<double>& next) {
  const std::size_t n = x.size();
  begin(n);
  std::copy(g.begin(), g.end(), output());
  next.resize(n);
  if (extrapolate(x.data(), next.data())) return true;
  std::copy(last_g_.begin(), last_g_.end(), next.begin());
  return false;
}

bool AndersonAccelerator::extrapolate(const double* x, double* next) {
  const PassSums sums = pass(x, 0, size_);
  if (!fit(std::span<const PassSums>(&sums, 1))) return false;
  mix(next, 0, size_);
  return true;
}

void AndersonAccelerator::begin(std::size_t n) {
  if (n != size_) {
    size_ = n;
    constexpr std::size_t kLine = kCacheLine / sizeof(double);
    constexpr std::size_t kFloatLine = kCacheLine / sizeof(float);
    stride_ = (n + kLine - 1) / kLine * kLine;
    f_stride_ = (n + kFloatLine - 1) / kFloatLine * kFloatLine;
    last_f_.resize(n);
    last_g_.resize(n);
    delta_f_.resize(f_stride_ * static_cast<std::size_t>(depth_));
    delta_g_.resize(stride_ * static_cast<std::size_t>(depth_));
    reset();
  }
  first_ = !has_last_;
  has_last_ = true;
  if (first_) return;
  // the new difference goes to a free slot, or over the oldest one
  slot_ = count_ < depth_ ? count_ : (newest_ + 1) % depth_;
  count_ = std::min(count_ + 1, depth_);
  newest_ = slot_;
  n_others_ = 0;
  for (int s = 0; s < count_; ++s) {
    if (s != slot_) others_[static_cast<std::size_t>(n_others_++)] = s;
  }
}

double* AndersonAccelerator::output() {
  // before a history every slot is free: slot 0
  return delta_g_.data() + static_cast<std::size_t>(first_ ? 0 : slot_) * stride_;
}

AndersonAccelerator::PassSums AndersonAccelerator::pass(const double* x, std::size_t first,
                                                        std::size_t last) {
  PassSums sums;
  const double* const g = output();
  if (first_) {
    // x may be last_g_: each entry is read before it is written
    for (std::size_t i = first; i < last; ++i) {
      const double gi = g[i];
      last_f_[i] = gi - x[i];
      last_g_[i] = gi;
    }
    return sums;
  }
  // pass 1: f = g − x, the new differences, ΔF_newᵀΔF_s and ΔF_sᵀ f for every slot; g is read
  // from the new slot's ΔG, which it turns into g − last g
  FSlotPointers other_f{};
  for (int j = 0; j < n_others_; ++j) {
    other_f[static_cast<std::size_t>(j)] =
        delta_f_.data() +
        static_cast<std::size_t>(others_[static_cast<std::size_t>(j)]) * f_stride_ + first;
  }
  float* new_f = delta_f_.data() + static_cast<std::size_t>(slot_) * f_stride_;
  double* new_g = delta_g_.data() + static_cast<std::size_t>(slot_) * stride_;
  const PassOneVectors vectors{x + first,     last_f_.data() + first, last_g_.data() + first,
                               new_f + first, new_g + first,          last - first};
  CDP_LANES_FOR_CPU(pass_one)(vectors, other_f, n_others_, sums);
  return sums;
}

bool AndersonAccelerator::fit(std::span<const PassSums> ranges) {
  if (first_) return false;
  // the ranges' sums added range by range
  PassSums sums = ranges.front();
  for (std::size_t r = 1; r < ranges.size(); ++r) sums.add(ranges[r]);
  SlotWeights& cross = sums.cross;  // ΔF_newᵀ ΔF_other[j]
  SlotWeights& rhs = sums.rhs;      // ΔF_other[j]ᵀ f, then ΔF_newᵀ f of the new slot
  const auto at = [](int s, int t) {
    return static_cast<std::size_t>(s) * kMaxDepth + static_cast<std::size_t>(t);
  };
  gram_[at(slot_, slot_)] = sums.new_new;
  for (int j = 0; j < n_others_; ++j) {
    const int s = others_[static_cast<std::size_t>(j)];
    gram_[at(slot_, s)] = gram_[at(s, slot_)] = cross[static_cast<std::size_t>(j)];
  }

  // normal equations (ΔFᵀΔF + λ I) γ = ΔFᵀ f over the slots [others..., slot], λ a
  // relative Tikhonov term against nearly parallel differences; fixed capacity, no allocation
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDepth, kMaxDepth>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDepth, 1>;
  const int k = n_others_ + 1;
  std::array<int, kMaxDepth> slots = others_;
  slots[static_cast<std::size_t>(n_others_)] = slot_;
  rhs[static_cast<std::size_t>(n_others_)] = sums.new_rhs;
  Small normal(k, k);
  SmallVector right(k);
  for (int a = 0; a < k; ++a) {
    right(a) = rhs[static_cast<std::size_t>(a)];
    for (int b = 0; b < k; ++b) {
      normal(a, b) =
          gram_[at(slots[static_cast<std::size_t>(a)], slots[static_cast<std::size_t>(b)])];
    }
  }
  const double lambda = 1e-12 * normal.trace();
  normal.diagonal().array() += lambda > 0.0 ? lambda : 1e-300;
  const SmallVector gamma = normal.ldlt().solve(right);
  if (!gamma.allFinite()) return false;
  fitted_ = k;
  for (int a = 0; a < k; ++a) {
    others_[static_cast<std::size_t>(a)] = slots[static_cast<std::size_t>(a)];
    weights_[static_cast<std::size_t>(a)] = gamma(a);
  }
  return true;
}

void AndersonAccelerator::mix(double* next, std::size_t first, std::size_t last) const {
  // pass 2: next = g − Σ γ_s ΔG_s, g the last output
  GSlotPointers slot_g{};
  for (int a = 0; a < fitted_; ++a) {
    slot_g[static_cast<std::size_t>(a)] =
        delta_g_.data() + static_cast<std::size_t>(others_[static_cast<std::size_t>(a)]) * stride_ +
        first;
  }
  CDP_LANES_FOR_CPU(mix)
  (last_g_.data() + first, slot_g, weights_, fitted_, next + first, last - first);
}

}  // namespace cdpowder
