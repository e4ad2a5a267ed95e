// cell_grid.hpp — the broad phase: a uniform grid of cells, periodic in x and y and
// bounded by the spheres' extent in z, rebuilt every step by a counting sort (O(N)).
// A cell edge ≥ the largest centre distance that can still be a candidate, so every
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
  /// Sorts the positions (already wrapped into the box) into cells of edge ≥ min_cell_edge [R].
  void rebuild(const std::vector<Vec3>& positions, const PeriodicBox& box, double min_cell_edge);

  /// Calls visit(j) for every sphere j in the same or a neighbouring cell of sphere i
  /// (each once; i itself included), in cell order.
  template <typename Visitor>
  void for_each_near(BodyIndex i, Visitor&& visit) const;

  [[nodiscard]] int cells_x() const { return nx_; }

  [[nodiscard]] int cells_y() const { return ny_; }

  [[nodiscard]] int cells_z() const { return nz_; }

 private:
  [[nodiscard]] int cell_index(int cx, int cy, int cz) const { return (cz * ny_ + cy) * nx_ + cx; }

  /// Distinct neighbour cells of (cx, cy, cz) including itself; returns their count.
  int neighbour_cells(int cx, int cy, int cz, std::array<int, 27>& out) const;

  int nx_ = 1;
  int ny_ = 1;
  int nz_ = 1;
  std::vector<int> cell_of_;  ///< cell of every sphere
  std::vector<std::uint32_t>
      cell_start_;  ///< spheres of cell c: sorted_[cell_start_[c] .. cell_start_[c+1])
  std::vector<BodyIndex> sorted_;  ///< sphere indices ordered by cell
};

template <typename Visitor>
void CellGrid::for_each_near(BodyIndex i, Visitor&& visit) const {
  const int c = cell_of_[i];
  const int cx = c % nx_;
  const int cy = (c / nx_) % ny_;
  const int cz = c / (nx_ * ny_);
  std::array<int, 27> neighbours{};
  const int count = neighbour_cells(cx, cy, cz, neighbours);
  for (int k = 0; k < count; ++k) {
    const int nc = neighbours[k];
    for (std::uint32_t t = cell_start_[nc]; t < cell_start_[nc + 1]; ++t) visit(sorted_[t]);
  }
}

}  // namespace cdpowder
