// anderson.cpp — the least-squares mixing of Anderson acceleration (type II).
#include "cdpowder/solver/anderson.hpp"

#include <Eigen/Dense>

namespace cdpowder {

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

void AndersonAccelerator::reset() {
  for (auto& v : delta_f_) spare_.push_back(std::move(v));
  for (auto& v : delta_g_) spare_.push_back(std::move(v));
  delta_f_.clear();
  delta_g_.clear();
  last_f_.clear();
  last_g_.clear();
}

bool AndersonAccelerator::extrapolate(const std::vector<double>& x, const std::vector<double>& g,
                                      std::vector<double>& next) {
  const std::size_t n = x.size();
  const auto take = [&]() {
    std::vector<double> v;
    if (!spare_.empty()) {
      v = std::move(spare_.back());
      spare_.pop_back();
    }
    v.resize(n);
    return v;
  };
  // f = g − x; store the differences to the previous sweep
  std::vector<double> f = take();
  for (std::size_t i = 0; i < n; ++i) f[i] = g[i] - x[i];
  if (last_f_.size() == n) {
    std::vector<double> df = take();
    std::vector<double> dg = take();
    for (std::size_t i = 0; i < n; ++i) {
      df[i] = f[i] - last_f_[i];
      dg[i] = g[i] - last_g_[i];
    }
    if (static_cast<int>(delta_f_.size()) == depth_) {
      // drop the oldest difference and shift its Gram products out
      spare_.push_back(std::move(delta_f_.front()));
      spare_.push_back(std::move(delta_g_.front()));
      delta_f_.pop_front();
      delta_g_.pop_front();
      const std::size_t kept = delta_f_.size();
      for (std::size_t i = 0; i < kept; ++i) {
        for (std::size_t j = 0; j < kept; ++j) {
          gram_[i * kMaxDepth + j] = gram_[(i + 1) * kMaxDepth + (j + 1)];
        }
      }
    }
    delta_f_.push_back(std::move(df));
    delta_g_.push_back(std::move(dg));
    const std::size_t last = delta_f_.size() - 1;
    for (std::size_t j = 0; j <= last; ++j) {
      gram_[last * kMaxDepth + j] = gram_[j * kMaxDepth + last] = dot(delta_f_[last], delta_f_[j]);
    }
  } else {
    last_f_.resize(n);
    last_g_.resize(n);
  }
  last_f_.swap(f);
  spare_.push_back(std::move(f));
  last_g_.assign(g.begin(), g.end());

  next.assign(g.begin(), g.end());
  const auto k = static_cast<Eigen::Index>(delta_f_.size());
  if (k == 0) return false;
  // normal equations (ΔFᵀΔF + λ I) γ = ΔFᵀ f, λ a relative Tikhonov term against
  // nearly parallel differences; fixed-capacity matrices, no allocation
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDepth, kMaxDepth>;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDepth, 1>;
  Small normal(k, k);
  SmallVector rhs(k);
  for (Eigen::Index a = 0; a < k; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    rhs(a) = dot(delta_f_[ua], last_f_);
    for (Eigen::Index b = 0; b < k; ++b) {
      normal(a, b) = gram_[ua * kMaxDepth + static_cast<std::size_t>(b)];
    }
  }
  const double lambda = 1e-12 * normal.trace();
  normal.diagonal().array() += lambda > 0.0 ? lambda : 1e-300;
  const SmallVector gamma = normal.ldlt().solve(rhs);
  if (!gamma.allFinite()) return false;
  for (Eigen::Index a = 0; a < k; ++a) {
    const std::vector<double>& dg = delta_g_[static_cast<std::size_t>(a)];
    const double c = gamma(a);
    for (std::size_t i = 0; i < n; ++i) next[i] -= c * dg[i];
  }
  return true;
}

}  // namespace cdpowder
