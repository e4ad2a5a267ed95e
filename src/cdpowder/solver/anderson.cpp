// anderson.cpp — the least-squares mixing of Anderson acceleration (type II).
#include "cdpowder/solver/anderson.hpp"

#include "cdpowder/solver/lanes.hpp"

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

using SlotPointers = std::array<const double*, AndersonAccelerator::kMaxDepth>;
using SlotWeights = std::array<double, AndersonAccelerator::kMaxDepth>;

/// The vectors pass 1 streams through: the iterates x and g, the last f and g (updated), the
/// new slot's differences (written); n doubles each.
struct PassOneVectors {
  const double* x;
  const double* g;
  double* last_f;
  double* last_g;
  double* new_f;
  double* new_g;
  std::size_t n;
};

/// What pass 1 finds: ΔF_newᵀ ΔF_other[j], ΔF_other[j]ᵀ f, ΔF_newᵀ ΔF_new, ΔF_newᵀ f.
struct PassOneSums {
  SlotWeights cross{};
  SlotWeights rhs{};
  double new_new = 0.0;
  double new_rhs = 0.0;
};

// The passes over the long vectors, compiled for SSE2 (the x86-64 baseline) and for AVX2
// (chosen at run time, lanes.hpp): a 4-double vector is two SSE2 registers or one AVX
// register, the same operations on the same operands, so the same bits.
#define CDP_LANE_CODE "cdpowder/solver/anderson_lanes.inc"
#include "cdpowder/solver/lanes_instantiate.inc"

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
  if (n != size_) {
    size_ = n;
    constexpr std::size_t kLine = kCacheLine / sizeof(double);
    stride_ = (n + kLine - 1) / kLine * kLine;
    last_f_.resize(n);
    last_g_.resize(n);
    delta_f_.resize(stride_ * static_cast<std::size_t>(depth_));
    delta_g_.resize(stride_ * static_cast<std::size_t>(depth_));
    reset();
  }
  next.resize(n);
  if (!has_last_) {
    for (std::size_t i = 0; i < n; ++i) {
      last_f_[i] = g[i] - x[i];
      last_g_[i] = g[i];
      next[i] = g[i];
    }
    has_last_ = true;
    return false;
  }

  // the new difference goes to a free slot, or over the oldest one
  const int slot = count_ < depth_ ? count_ : (newest_ + 1) % depth_;
  count_ = std::min(count_ + 1, depth_);
  newest_ = slot;
  std::array<int, kMaxDepth> others{};  // the other slots in the fit
  int n_others = 0;
  for (int s = 0; s < count_; ++s) {
    if (s != slot) others[static_cast<std::size_t>(n_others++)] = s;
  }
  SlotPointers other_f{};
  for (int j = 0; j < n_others; ++j) {
    other_f[static_cast<std::size_t>(j)] =
        delta_f_.data() + static_cast<std::size_t>(others[static_cast<std::size_t>(j)]) * stride_;
  }
  double* new_f = delta_f_.data() + static_cast<std::size_t>(slot) * stride_;
  double* new_g = delta_g_.data() + static_cast<std::size_t>(slot) * stride_;

  // pass 1: f = g − x, the new differences, ΔF_newᵀΔF_s and ΔF_sᵀ f for every slot
  const PassOneVectors vectors{x.data(), g.data(), last_f_.data(), last_g_.data(), new_f, new_g, n};
  PassOneSums sums;
  CDP_LANES_FOR_CPU(pass_one)(vectors, other_f, n_others, sums);
  SlotWeights& cross = sums.cross;  // ΔF_newᵀ ΔF_other[j]
  SlotWeights& rhs = sums.rhs;      // ΔF_other[j]ᵀ f, then ΔF_newᵀ f of the new slot
  const auto at = [](int s, int t) {
    return static_cast<std::size_t>(s) * kMaxDepth + static_cast<std::size_t>(t);
  };
  gram_[at(slot, slot)] = sums.new_new;
  for (int j = 0; j < n_others; ++j) {
    const int s = others[static_cast<std::size_t>(j)];
    gram_[at(slot, s)] = gram_[at(s, slot)] = cross[static_cast<std::size_t>(j)];
  }

  // normal equations (ΔFᵀΔF + λ I) γ = ΔFᵀ f over the slots [others..., slot], λ a
  // relative Tikhonov term against nearly parallel differences; fixed capacity, no allocation
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDepth, kMaxDepth>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDepth, 1>;
  const int k = n_others + 1;
  others[static_cast<std::size_t>(n_others)] = slot;
  rhs[static_cast<std::size_t>(n_others)] = sums.new_rhs;
  Small normal(k, k);
  SmallVector right(k);
  for (int a = 0; a < k; ++a) {
    right(a) = rhs[static_cast<std::size_t>(a)];
    for (int b = 0; b < k; ++b) {
      normal(a, b) =
          gram_[at(others[static_cast<std::size_t>(a)], others[static_cast<std::size_t>(b)])];
    }
  }
  const double lambda = 1e-12 * normal.trace();
  normal.diagonal().array() += lambda > 0.0 ? lambda : 1e-300;
  const SmallVector gamma = normal.ldlt().solve(right);
  if (!gamma.allFinite()) {
    std::copy(g.begin(), g.end(), next.begin());
    return false;
  }

  // pass 2: next = g − Σ γ_s ΔG_s
  SlotPointers slot_g{};
  SlotWeights weights{};
  for (int a = 0; a < k; ++a) {
    slot_g[static_cast<std::size_t>(a)] =
        delta_g_.data() + static_cast<std::size_t>(others[static_cast<std::size_t>(a)]) * stride_;
    weights[static_cast<std::size_t>(a)] = gamma(a);
  }
  CDP_LANES_FOR_CPU(mix)(g.data(), slot_g, weights, k, next.data(), n);
  return true;
}

}  // namespace cdpowder
