// anderson.cpp — the least-squares mixing of Anderson acceleration (type II).
#include "cdpowder/solver/anderson.hpp"

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

/// The sums of pass 1 are kept in kSumLanes partial sums, element i adding to partial
/// i mod kSumLanes, and the partials are added at the end as (s0 + s1) + (s2 + s3). The order
/// is fixed by this code, not by the vector width the compiler picks (GCC lowers a 4-double
/// vector to two SSE2 registers or one AVX register: the same operations on the same
/// operands), so the mixing gives the same bits on every x86-64 machine, and the loops run
/// 4 elements a step instead of one long chain of dependent additions.
constexpr int kSumLanes = 2;
using Lanes = double __attribute__((vector_size(kSumLanes * sizeof(double))));

[[gnu::always_inline]] inline Lanes load_lanes(const double* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store_lanes(double* p, Lanes v) {
  std::memcpy(p, &v, sizeof v);
}

/// s0 + s1
[[gnu::always_inline]] inline double total(Lanes s) {
  return s[0] + s[1];
}

/// Pass 1 of a mixing step: the new differences and their inner products with the stored
/// ones, in one stream over memory.
struct PassOne {
  const double* x;
  const double* g;
  double* last_f;
  double* last_g;
  double* new_f;
  double* new_g;
  std::size_t n;

  /// kCount = number of other slots, or −1 for a count known only at run time.
  template <int kCount>
  void run(const std::array<const double*, AndersonAccelerator::kMaxDepth>& other_f,
           std::array<double, AndersonAccelerator::kMaxDepth>& cross_out,
           std::array<double, AndersonAccelerator::kMaxDepth>& rhs_out, double& new_new_out,
           double& new_rhs_out, int runtime_count) const {
    const int count = kCount >= 0 ? kCount : runtime_count;
    std::array<Lanes, AndersonAccelerator::kMaxDepth> cross{};
    std::array<Lanes, AndersonAccelerator::kMaxDepth> rhs{};
    Lanes new_new{};
    Lanes new_rhs{};
    const std::size_t whole = n - n % kSumLanes;
    for (std::size_t i = 0; i < whole; i += kSumLanes) {
      const Lanes gi = load_lanes(g + i);
      const Lanes f = gi - load_lanes(x + i);
      const Lanes df = f - load_lanes(last_f + i);
      store_lanes(new_f + i, df);
      store_lanes(new_g + i, gi - load_lanes(last_g + i));
      store_lanes(last_f + i, f);
      store_lanes(last_g + i, gi);
      new_new += df * df;
      new_rhs += df * f;
      for (int j = 0; j < count; ++j) {
        const Lanes d = load_lanes(other_f[static_cast<std::size_t>(j)] + i);
        cross[static_cast<std::size_t>(j)] += df * d;
        rhs[static_cast<std::size_t>(j)] += d * f;
      }
    }
    for (std::size_t i = whole; i < n; ++i) {  // the last n mod 4 elements, lane i mod 4
      const std::size_t lane = i % kSumLanes;
      const double f = g[i] - x[i];
      const double df = f - last_f[i];
      new_f[i] = df;
      new_g[i] = g[i] - last_g[i];
      last_f[i] = f;
      last_g[i] = g[i];
      new_new[lane] += df * df;
      new_rhs[lane] += df * f;
      for (int j = 0; j < count; ++j) {
        const double d = other_f[static_cast<std::size_t>(j)][i];
        cross[static_cast<std::size_t>(j)][lane] += df * d;
        rhs[static_cast<std::size_t>(j)][lane] += d * f;
      }
    }
    for (int j = 0; j < count; ++j) {
      cross_out[static_cast<std::size_t>(j)] = total(cross[static_cast<std::size_t>(j)]);
      rhs_out[static_cast<std::size_t>(j)] = total(rhs[static_cast<std::size_t>(j)]);
    }
    new_new_out = total(new_new);
    new_rhs_out = total(new_rhs);
  }
};

/// Pass 2: next = g − Σ_a w_a ΔG_a, the terms subtracted in slot order (element by element,
/// so 4 at a time gives the bits of one at a time).
template <int kCount>
void mix(const double* g, const std::array<const double*, AndersonAccelerator::kMaxDepth>& slot_g,
         const std::array<double, AndersonAccelerator::kMaxDepth>& weights, int runtime_count,
         double* next, std::size_t n) {
  const int count = kCount >= 0 ? kCount : runtime_count;
  const std::size_t whole = n - n % kSumLanes;
  for (std::size_t i = 0; i < whole; i += kSumLanes) {
    Lanes v = load_lanes(g + i);
    for (int a = 0; a < count; ++a) {
      v -= weights[static_cast<std::size_t>(a)] *
           load_lanes(slot_g[static_cast<std::size_t>(a)] + i);
    }
    store_lanes(next + i, v);
  }
  for (std::size_t i = whole; i < n; ++i) {
    double v = g[i];
    for (int a = 0; a < count; ++a) {
      v -= weights[static_cast<std::size_t>(a)] * slot_g[static_cast<std::size_t>(a)][i];
    }
    next[i] = v;
  }
}

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

bool AndersonAccelerator::extrapolate(const std::vector<double>& x, const std::vector<double>& g,
                                      std::vector<double>& next) {
  const std::size_t n = x.size();
  if (n != size_) {
    size_ = n;
    last_f_.resize(n);
    last_g_.resize(n);
    delta_f_.resize(n * static_cast<std::size_t>(depth_));
    delta_g_.resize(n * static_cast<std::size_t>(depth_));
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
  std::array<const double*, kMaxDepth> other_f{};
  for (int j = 0; j < n_others; ++j) {
    other_f[static_cast<std::size_t>(j)] =
        delta_f_.data() + static_cast<std::size_t>(others[static_cast<std::size_t>(j)]) * n;
  }
  double* new_f = delta_f_.data() + static_cast<std::size_t>(slot) * n;
  double* new_g = delta_g_.data() + static_cast<std::size_t>(slot) * n;

  // pass 1: f = g − x, the new differences, ΔF_newᵀΔF_s and ΔF_sᵀ f for every slot
  std::array<double, kMaxDepth> cross{};  // ΔF_newᵀ ΔF_other[j]
  std::array<double, kMaxDepth> rhs{};    // ΔF_other[j]ᵀ f
  double new_new = 0.0;
  double new_rhs = 0.0;
  const PassOne pass{x.data(), g.data(), last_f_.data(), last_g_.data(), new_f, new_g, n};
  dispatch_by_count(n_others, [&](auto count) {
    pass.run<decltype(count)::value>(other_f, cross, rhs, new_new, new_rhs, n_others);
  });
  const auto at = [](int s, int t) {
    return static_cast<std::size_t>(s) * kMaxDepth + static_cast<std::size_t>(t);
  };
  gram_[at(slot, slot)] = new_new;
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
  rhs[static_cast<std::size_t>(n_others)] = new_rhs;
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
  std::array<const double*, kMaxDepth> slot_g{};
  std::array<double, kMaxDepth> weights{};
  for (int a = 0; a < k; ++a) {
    slot_g[static_cast<std::size_t>(a)] =
        delta_g_.data() + static_cast<std::size_t>(others[static_cast<std::size_t>(a)]) * n;
    weights[static_cast<std::size_t>(a)] = gamma(a);
  }
  dispatch_by_count(k, [&](auto count) {
    mix<decltype(count)::value>(g.data(), slot_g, weights, k, next.data(), n);
  });
  return true;
}

}  // namespace cdpowder
