// anderson.hpp — Anderson acceleration of the NLGS fixed-point map (physics.md §17).
//
// Why: a heavy free body closing the load path (the piston, M_P = 240 sphere masses)
// gives the Delassus operator a near-null mode — one uniform force along the load path
// that changes only the piston's velocity — so plain Gauss–Seidel needs ~H M_P/m sweeps
// (measured: a 12-sphere column under the paper's piston, 66 000 sweeps to 1e-10). A few
// smooth slow modes are exactly what Anderson mixing removes: with the last m sweeps it
// takes the combination of iterates whose residual is smallest (Walker & Ni, SIAM J.
// Numer. Anal. 49 (2011) 1715, "type II"). Same column: 31 sweeps with m = 5.
// It needs a stationary map, so the visiting order is fixed within a step.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <vector>

namespace cdpowder {

class AndersonAccelerator {
 public:
  static constexpr int kMaxDepth = 16;  ///< the fit is a kMaxDepth × kMaxDepth problem at most

  /// depth m (clamped to [1, kMaxDepth]): how many past differences enter the fit.
  explicit AndersonAccelerator(int depth = 5)
      : depth_(depth < 1 ? 1 : (depth > kMaxDepth ? kMaxDepth : depth)) {}

  /// Forgets the history (start of a step, or after a rejected extrapolation).
  void reset();

  /// Given the iterate x the sweep started from and g = G(x) the sweep produced, returns
  /// in `next` the accelerated iterate g − ΔG γ, γ = argmin |f − ΔF γ|, f = g − x.
  /// Returns false (and next = g) while there is no history yet.
  bool extrapolate(const std::vector<double>& x, const std::vector<double>& g,
                   std::vector<double>& next);

 private:
  int depth_;
  std::vector<double> last_f_;
  std::vector<double> last_g_;
  std::deque<std::vector<double>> delta_f_;  ///< f_{j+1} − f_j
  std::deque<std::vector<double>> delta_g_;  ///< g_{j+1} − g_j
  std::vector<std::vector<double>> spare_;   ///< recycled buffers: no allocation in steady state
  /// ΔF_iᵀΔF_j of the stored differences, kept up to date as differences come and go, so
  /// a sweep computes only the new products (row-major, kMaxDepth × kMaxDepth).
  std::array<double, kMaxDepth * kMaxDepth> gram_{};
};

}  // namespace cdpowder
