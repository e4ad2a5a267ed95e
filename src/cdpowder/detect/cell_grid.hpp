// cell_grid.hpp — the broad phase: a uniform grid of cells, periodic in x and y and
// bounded by the spheres' extent in z, rebuilt by a counting sort (O(N)) with the candidate
// list. A cell edge ≥ the largest centre distance that can still be a candidate, so every
// candidate pair sits in the same or a neighbouring cell (physics.md §4.3).
#pragma once

#include "cdpowder/core/index.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/periodic_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace cdpowder {

/// Cells of edge `edge` along `length`: at least one.
inline double cells_along(double length, double edge) {
  return std::max(1.0, std::floor(length / edge));
}

/// The edge min_edge × 2^k with the smallest k ≥ 0 for which cell_count(edge) ≤ max_cells.
/// Memory O(N): in a region far wider than its spheres fill (a cell of 10^9 R for 10^3
/// spheres once asked for 10^10 cells, std::bad_alloc) the cells grow instead; larger cells
/// find the same neighbours. (An edge ≤ 0, asked for by no caller, would never grow: 1 then.)
template <typename CellCount>
double edge_within(double min_edge, double max_cells, const CellCount& cell_count) {
  double edge = min_edge > 0.0 ? min_edge : 1.0;
  while (cell_count(edge) > max_cells) edge *= 2.0;
  return edge;
}

class CellGrid {
 public:
  /// A stretch [first, last) of sorted(): the spheres of one cell or of neighbouring cells
  /// next to each other along x.
  struct Run {
    std::uint32_t first = 0;
    std::uint32_t last = 0;
  };

  /// The most runs near_runs gives: three layers in z times three rows in y, each row one
  /// stretch of cells along x or two where it wraps.
  static constexpr int kMaxRuns = 18;

  /// Sorts the positions (already wrapped into the box) into cells of edge ≥ min_cell_edge [R].
  void rebuild(const std::vector<Vec3>& positions, const PeriodicBox& box, double min_cell_edge);

  /// The spheres in the same or a neighbouring cell of sphere i (i itself included), each
  /// once, as runs of sorted(): at most 2 per row of three cells along x, so a sphere's
  /// neighbourhood is a few contiguous stretches rather than 27 cells. Returns their count.
  int near_runs(BodyIndex i, std::array<Run, kMaxRuns>& runs) const;

  /// The spheres ordered by cell, and their positions in that order (copies of the positions
  /// of the last rebuild, so that a pass over a run reads contiguous memory).
  [[nodiscard]] const std::vector<BodyIndex>& sorted() const { return sorted_; }

  [[nodiscard]] const std::vector<Vec3>& sorted_positions() const { return sorted_position_; }

  [[nodiscard]] int cells_x() const { return nx_; }

  [[nodiscard]] int cells_y() const { return ny_; }

  [[nodiscard]] int cells_z() const { return nz_; }

 private:
  [[nodiscard]] int cell_index(int cx, int cy, int cz) const { return (cz * ny_ + cy) * nx_ + cx; }

  /// Appends to `runs` the neighbour cells of cx in the row (cy, cz): one run, or two where
  /// the row wraps; the whole row when it has fewer than three cells.
  void add_row(int cx, int cy, int cz, std::array<Run, kMaxRuns>& runs, int& count) const;

  int nx_ = 1;
  int ny_ = 1;
  int nz_ = 1;
  std::vector<int> cell_of_;  ///< cell of every sphere
  std::vector<std::uint32_t>
      cell_start_;  ///< spheres of cell c: sorted_[cell_start_[c] .. cell_start_[c+1])
  std::vector<BodyIndex> sorted_;      ///< sphere indices ordered by cell
  std::vector<Vec3> sorted_position_;  ///< positions[sorted_[t]] [R]
};

}  // namespace cdpowder
