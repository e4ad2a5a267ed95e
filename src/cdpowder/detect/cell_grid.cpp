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
  sorted_position_.resize(n);
  for (std::size_t t = 0; t < n; ++t) sorted_position_[t] = positions[sorted_[t]];
  for (std::size_t c = cells; c > 0; --c) cell_start_[c] = cell_start_[c - 1];
  cell_start_[0] = 0;
}

int CellGrid::near_runs(BodyIndex i, std::array<Run, kMaxRuns>& runs) const {
  const int c = cell_of_[i];
  const int cx = c % nx_;
  const int cy = (c / nx_) % ny_;
  const int cz = c / (nx_ * ny_);
  int count = 0;
  // the layers cz − 1 … cz + 1 that exist (z is not periodic); in each the rows cy − 1 … cy + 1
  // wrapped in y, or every row where there are fewer than three (an offset ±1 would repeat one)
  const int z_last = std::min(cz + 1, nz_ - 1);
  for (int z = std::max(cz - 1, 0); z <= z_last; ++z) {
    if (ny_ < 3) {
      for (int y = 0; y < ny_; ++y) add_row(cx, y, z, runs, count);
    } else {
      add_row(cx, cy == 0 ? ny_ - 1 : cy - 1, z, runs, count);
      add_row(cx, cy, z, runs, count);
      add_row(cx, cy == ny_ - 1 ? 0 : cy + 1, z, runs, count);
    }
  }
  return count;
}

void CellGrid::add_row(int cx, int cy, int cz, std::array<Run, kMaxRuns>& runs, int& count) const {
  // the cells of a row are consecutive, and so are their spheres in sorted_
  const int row = cell_index(0, cy, cz);
  const auto add = [&](int first_x, int last_x) {
    const Run run{cell_start_[row + first_x], cell_start_[row + last_x + 1]};
    if (run.first < run.last) runs[count++] = run;
  };
  if (nx_ < 3) {
    add(0, nx_ - 1);  // every cell of the row is a neighbour, each once
  } else if (cx == 0) {
    add(0, 1);
    add(nx_ - 1, nx_ - 1);
  } else if (cx == nx_ - 1) {
    add(0, 0);
    add(nx_ - 2, nx_ - 1);
  } else {
    add(cx - 1, cx + 1);
  }
}

}  // namespace cdpowder
