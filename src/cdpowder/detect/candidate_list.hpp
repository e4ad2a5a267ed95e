// candidate_list.hpp — the sphere pairs that can become candidates before any sphere has
// moved far: a Verlet list (physics.md §4.3). Built from the cell grid with the step's
// candidate gap plus a margin, it holds every pair that can come within the candidate gap
// while the largest displacement since the build stays below half the margin left over.
// Detection then checks only the listed pairs each step and rebuilds the grid only when the
// list no longer covers the step, so the per-step cost of the broad phase drops from a grid
// rebuild to a pass over the list. The contacts a step gets are exactly those a fresh search
// finds: the list is a superset and every pair is tested against the step's own gap.
#pragma once

#include "cdpowder/core/index.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/detect/cell_grid.hpp"
#include "cdpowder/model/bodies.hpp"
#include "cdpowder/model/periodic_box.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

class CandidateList {
 public:
  /// Whether the list still holds every pair whose surface gap can be below `gap` now: the
  /// built gap covers `gap` plus twice the largest displacement since the build. Also false
  /// before the first build and when the sphere count or the cell changed.
  [[nodiscard]] bool covers(const Bodies& bodies, const PeriodicBox& box, double gap) const {
    return may_cover(bodies, box, gap) && covers_spheres(bodies, box, gap, 0, bodies.size());
  }

  /// covers() in two parts, so that the spheres can be checked in pieces: whether the list
  /// was built for these spheres and cell with a gap that leaves slack over `gap`, and whether
  /// none of spheres [first, last) has moved past the slack since the build.
  [[nodiscard]] bool may_cover(const Bodies& bodies, const PeriodicBox& box, double gap) const;
  [[nodiscard]] bool covers_spheres(const Bodies& bodies, const PeriodicBox& box, double gap,
                                    std::size_t first, std::size_t last) const;

  /// Lists every pair a < b (not both fixed) whose surface gap is below gap + margin, sorted
  /// by (a, b), and remembers the positions (wrapped into the box) it was built at. With
  /// `pieces`, the spheres are cut into the pieces of indices_per_piece (core/pieces.hpp),
  /// each listing its own pairs on the runner's threads: the same list, in the same order.
  void rebuild(const Bodies& bodies, const PeriodicBox& box, CellGrid& grid, double gap,
               double margin, PieceRunner* pieces = nullptr);

  struct Pair {
    BodyIndex a;
    BodyIndex b;
  };

  [[nodiscard]] const std::vector<Pair>& pairs() const { return pairs_; }

  /// Builds so far (for the benchmarks and tests).
  [[nodiscard]] std::int64_t builds() const { return builds_; }

 private:
  /// How far each sphere may have moved since the build with every pair within `gap` still
  /// listed: two spheres approach each other by at most the sum of their displacements (less
  /// a part in 1e9, so that round-off in the displacements never admits a miss) [R].
  [[nodiscard]] double slack(double gap) const { return 0.5 * (built_gap_ - gap) * (1.0 - 1e-9); }

  std::vector<Pair> pairs_;
  std::vector<Vec3> anchor_;  ///< positions at the build [R]
  PeriodicBox box_;
  double built_gap_ = -1.0;  ///< gap + margin of the build; < 0: never built [R]
  std::int64_t builds_ = 0;
  std::vector<BodyIndex> partners_;  ///< scratch of rebuild: one sphere's listed partners
  /// scratch of a rebuild in pieces: each piece's pairs and partners
  std::vector<std::vector<Pair>> piece_pairs_;
  std::vector<std::vector<BodyIndex>> piece_partners_;
};

}  // namespace cdpowder
