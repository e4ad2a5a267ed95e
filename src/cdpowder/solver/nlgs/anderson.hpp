// anderson.hpp — Anderson acceleration of the NLGS fixed-point map (physics.md §17).
//
// Why: a heavy free body closing the load path (the piston, M_P = 240 sphere masses)
// gives the Delassus operator a near-null mode — one uniform force along the load path
// that changes only the piston's velocity — so plain Gauss–Seidel needs ~H M_P/m passes
// (measured: a 12-sphere column under the paper's piston, 66 000 passes to 1e-10). A few
// smooth slow modes are exactly what Anderson mixing removes: with the last m passes it
// takes the combination of iterates whose residual is smallest (Walker & Ni, SIAM J.
// Numer. Anal. 49 (2011) 1715, "type II"). Same column: 31 passes with m = 5.
// It needs a stationary map, so the visiting order is fixed within a step.
//
// Cost: the vectors hold 4 to 8 values per contact (nlgs.cpp leaves out modes that are zero
// throughout a step), so for a paper-size packing they leave the
// L1/L2 caches and the mixing is bound by memory traffic. The history is a ring of
// contiguous slots (no shifting, no allocation after the first step of a size), and one
// pass computes the new differences together with all their inner products; a second pass
// forms the mixed iterate: ≈ 2m + 10 values moved per entry instead of ≈ 7m + 12. The pass's
// output g is written straight into the ring slot its difference will take (output()), and the
// last g doubles as the next iterate where no mixing is adopted, so the caller keeps one vector
// of iterates (x, then the mixed iterate), not two.
// The m stored differences ΔF are single precision (ΔG, the iterates, f and g stay double):
// with m = 5 and 8 values a contact that saves 160 of the history's 768 bytes. ΔF only
// decides the weights γ; the fit uses the rounded differences throughout (its Gram matrix and
// right-hand side are those of the stored vectors), so it stays a least-squares fit, and any γ
// gives an affine combination g − ΔG γ of the map's outputs. ΔG stays double: rounded, it would add
// about 6e-8 of the history's steps to every mixed iterate, a floor that stalled final static
// solves at 1e-6 (docs/lab/2026-11-30-memory-per-contact.md).
#pragma once

#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/solver/settings.hpp"

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace cdpowder {

class AndersonAccelerator {
 public:
  static constexpr int kMaxDepth = kMaxAndersonDepth;  ///< solver/settings.hpp

  /// depth m (clamped to [1, kMaxDepth]): how many past differences enter the fit.
  explicit AndersonAccelerator(int depth = 5) { set_depth(depth); }

  /// Changes m (clamped) and forgets the history; buffers are kept.
  void set_depth(int depth);

  int depth() const { return depth_; }

  /// Forgets the history (start of a step, or after the active set changed); keeps the
  /// buffers, so a new step of the same size allocates nothing.
  void reset();

  /// Given the iterate x the pass started from and g = G(x) the pass produced, returns
  /// in `next` the accelerated iterate g − ΔG γ, γ = argmin |f − ΔF γ|, f = g − x.
  /// Returns false (and next = g) while there is no history yet or the fit failed.
  /// `next` may be x or g (both are read before `next` is written). It copies g into output()
  /// and runs the stages below over one range [0, n).
  bool extrapolate(const AlignedVector<double>& x, const AlignedVector<double>& g,
                   AlignedVector<double>& next);

  /// The stages below over one range [0, n), once begin(n) was called and the pass's output
  /// is in output(): `next` ← the mixed iterate (true), or untouched (false: no history yet, or
  /// the fit failed; the next iterate is then last_output()). `next` may be x.
  bool extrapolate(const double* x, double* next);

  /// What pass 1 finds over a range: ΔF_newᵀ ΔF_other[j], ΔF_other[j]ᵀ f, ΔF_newᵀ ΔF_new,
  /// ΔF_newᵀ f.
  struct PassSums {
    std::array<double, kMaxDepth> cross{};
    std::array<double, kMaxDepth> rhs{};
    double new_new = 0.0;
    double new_rhs = 0.0;

    /// Adds the sums of the range that follows: this range's and then that one's.
    void add(const PassSums& next) {
      for (std::size_t j = 0; j < cross.size(); ++j) {
        cross[j] += next.cross[j];
        rhs[j] += next.rhs[j];
      }
      new_new += next.new_new;
      new_rhs += next.new_rhs;
    }
  };

  /// The mixing in stages, so that disjoint ranges of the vectors can be passed over by
  /// different threads (tiles.hpp): begin(n) once; the pass's output g written to output();
  /// pass(x, first, last) over ranges that cover [0, n) once each; fit(sums of the ranges, in a
  /// fixed order) — false while there is no history yet or the fit failed; then, if it returned
  /// true, mix(next, first, last) over ranges that cover [0, n). `next` must hold n doubles.
  void begin(std::size_t n);

  /// Where the pass's output g goes, n doubles, from begin() until pass() has read them: the
  /// ring slot of the new ΔG, which pass() turns into g − last g entry by entry (each entry read
  /// before it is written), or a free slot before there is a history. So no vector holds g
  /// beside the history (4–8 doubles a contact).
  [[nodiscard]] double* output();

  /// Pass 1 over [first, last): f = g − x with g from output(), the new differences and the
  /// sums of the fit. x may be last_output() (an iterate no mixing replaced).
  [[nodiscard]] PassSums pass(const double* x, std::size_t first, std::size_t last);
  bool fit(std::span<const PassSums> ranges);

  /// next = g − ΔG γ over [first, last), g = last_output(). `next` may be the x of the pass.
  void mix(double* next, std::size_t first, std::size_t last) const;

  /// The output g of the last pass, after pass() over a range: the next iterate wherever no
  /// mixing was adopted.
  [[nodiscard]] const double* last_output() const { return last_g_.data(); }

  /// Differences currently in the fit (≤ depth).
  int history() const { return count_; }

 private:
  int depth_ = 5;
  std::size_t size_ = 0;      ///< length n of the iterates the buffers are laid out for
  std::size_t stride_ = 0;    ///< n rounded up to whole cache lines of doubles (ΔG's slots)
  std::size_t f_stride_ = 0;  ///< n rounded up to whole cache lines of floats (ΔF's slots)
  bool has_last_ = false;
  int count_ = 0;   ///< stored differences
  int newest_ = 0;  ///< ring slot of the newest difference
  AlignedVector<double> last_f_;
  AlignedVector<double> last_g_;
  /// slot s holds f_{j+1} − f_j, rounded to single precision, in [s f_stride_, s f_stride_ + n)
  AlignedVector<float> delta_f_;
  AlignedVector<double> delta_g_;  ///< slot s holds g_{j+1} − g_j in [s stride_, s stride_ + n)
  /// ΔF_sᵀΔF_t between ring slots s and t (row-major, kMaxDepth × kMaxDepth): a pass
  /// computes only the products of its new difference.
  std::array<double, static_cast<std::size_t>(kMaxDepth) * kMaxDepth> gram_{};
  // the mixing under way (begin … mix)
  bool first_ = false;  ///< no history before it: pass only remembers f and g
  int slot_ = 0;        ///< ring slot of the new difference
  int n_others_ = 0;    ///< the other slots in the fit
  std::array<int, kMaxDepth> others_{};
  int fitted_ = 0;  ///< slots in the fit (others, then the new one)
  std::array<double, kMaxDepth> weights_{};
};

}  // namespace cdpowder
