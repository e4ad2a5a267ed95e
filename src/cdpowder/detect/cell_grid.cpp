// cell_grid.cpp — counting-sort construction of the periodic cell grid.
#include "cdpowder/detect/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

void CellGrid::rebuild(const std::vector<Vec3>& positions, const PeriodicBox& box,
                       double min_cell_edge) {
  const std::size_t n = positions.size();
  double z_min = 0.0;
  double z_max = 0.0;
  if (n > 0) {
    z_min = z_max = positions[0].z();
    for (const Vec3& p : positions) {
      z_min = std::min(z_min, p.z());
      z_max = std::max(z_max, p.z());
    }
  }
  // at most kMaxCellsPerSphere cells per sphere (edge_within); a packing has a few, so its
  // grid is the one of edge min_cell_edge
  constexpr double kMaxCellsPerSphere = 64.0;
  constexpr double kMinCellLimit = 4096.0;
  const double edge = edge_within(
      min_cell_edge, std::max(kMinCellLimit, kMaxCellsPerSphere * static_cast<double>(n)),
      [&](double e) {
        return cells_along(box.lx, e) * cells_along(box.ly, e) *
               (cells_along(z_max - z_min, e) + 1.0);
      });
  nx_ = static_cast<int>(cells_along(box.lx, edge));
  ny_ = static_cast<int>(cells_along(box.ly, edge));
  nz_ = static_cast<int>(cells_along(z_max - z_min, edge)) + 1;
  const double edge_x = box.lx / nx_;
  const double edge_y = box.ly / ny_;

  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_ * nz_;
  cell_start_.assign(cells + 1, 0);
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = positions[i];
    const int cx = std::clamp(static_cast<int>(p.x() / edge_x), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>(p.y() / edge_y), 0, ny_ - 1);
    const int cz = std::clamp(static_cast<int>((p.z() - z_min) / edge), 0, nz_ - 1);
    cell_of_[i] = cell_index(cx, cy, cz);
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  sorted_.resize(n);
  std::vector<std::uint32_t>& fill = cell_start_;  // reuse as cursors, then shift back
  for (std::size_t i = 0; i < n; ++i) sorted_[fill[cell_of_[i]]++] = static_cast<BodyIndex>(i);
  for (std::size_t c = cells; c > 0; --c) cell_start_[c] = cell_start_[c - 1];
  cell_start_[0] = 0;
}

int CellGrid::neighbour_cells(int cx, int cy, int cz, std::array<int, 27>& out) const {
  int count = 0;
  const bool may_repeat = nx_ < 3 || ny_ < 3;
  for (int dz = -1; dz <= 1; ++dz) {
    const int z = cz + dz;
    if (z < 0 || z >= nz_) continue;  // z is not periodic
    for (int dy = -1; dy <= 1; ++dy) {
      const int y = (cy + dy + ny_) % ny_;
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = (cx + dx + nx_) % nx_;
        const int c = cell_index(x, y, z);
        // with fewer than three cells along x or y, offsets ±1 wrap onto the same cell
        if (!may_repeat || std::find(out.begin(), out.begin() + count, c) == out.begin() + count) {
          out[count++] = c;
        }
      }
    }
  }
  return count;
}

}  // namespace cdpowder
