// tiles.cpp — the grid, each sphere's tile and each contact's part (tiles.hpp).
#include "cdpowder/solver/nlgs/tiles.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

namespace {

/// Even tiles at least `width` wide along a period of `length`, or 1.
std::uint32_t tiles_along(double length, double width) {
  if (!(width > 0.0) || !(length >= 2.0 * width)) return 1;
  // an index type's worth at most: 2^15 tiles a side is 10^9 tiles
  const double pairs = std::min(std::floor(length / (2.0 * width)), 16384.0);
  return 2 * static_cast<std::uint32_t>(pairs);
}

/// The tile of coordinate x ∈ [0, L) among n tiles of width L/n.
std::uint32_t tile_of(double x, double length, std::uint32_t n) {
  if (n == 1) return 0;
  const double at = std::floor(x / length * static_cast<double>(n));
  // a coordinate outside [0, L) (not wrapped yet) is held to the grid
  return static_cast<std::uint32_t>(std::clamp(at, 0.0, static_cast<double>(n - 1)));
}

/// The lower of two tiles i, j along a direction of n tiles when they are neighbours (equal,
/// or j = i + 1 mod n), through `lower`; false when they are further apart.
bool lower_neighbour(std::uint32_t i, std::uint32_t j, std::uint32_t n, std::uint32_t& lower) {
  if (i == j || (i + 1) % n == j) {
    lower = i;
    return true;
  }
  if ((j + 1) % n == i) {
    lower = j;
    return true;
  }
  return false;
}

}  // namespace

TileGrid tile_grid(const PeriodicBox& box, double max_radius, double width) {
  const double w = width > 0.0 ? width : kTileWidthRadii * std::max(max_radius, 0.0);
  return {tiles_along(box.lx, w), tiles_along(box.ly, w)};
}

std::uint32_t StepTiles::pair_part(const PairProblem& p) const {
  std::uint32_t x = 0;
  std::uint32_t y = 0;
  if (!lower_neighbour(sphere_x[p.a], sphere_x[p.b], grid.nx, x) ||
      !lower_neighbour(sphere_y[p.a], sphere_y[p.b], grid.ny, y)) {
    return hub();
  }
  return part_of_tile[y * grid.nx + x];
}

void assign_tiles(const std::vector<Vec3>& positions, const PeriodicBox& box, double max_radius,
                  double width, const Contacts& contacts, StepTiles& tiles, PieceRunner* runner) {
  tiles.sphere_part.clear();
  tiles.grid = tile_grid(box, max_radius, width);
  const TileGrid grid = tiles.grid;
  if (contacts.pairs.size() < kMinPairsToTile || grid.tiles() == 1) {
    tiles.grid = {};
    tiles.phase_parts = {0, 1, 1, 1, 1};
    return;
  }
  // parts in pass order: phase (i mod 2, j mod 2) = (0,0), (1,0), (0,1), (1,1), each phase's
  // tiles in index order
  tiles.part_of_tile.resize(grid.tiles());
  std::uint32_t part = 0;
  for (std::uint32_t phase = 0; phase < kTilePhases; ++phase) {
    tiles.phase_parts[phase] = part;
    for (std::uint32_t iy = phase / 2; iy < grid.ny; iy += 2) {
      for (std::uint32_t ix = phase % 2; ix < grid.nx; ix += 2) {
        tiles.part_of_tile[iy * grid.nx + ix] = part++;
      }
    }
  }
  tiles.phase_parts[kTilePhases] = part;
  const std::size_t n = positions.size();
  tiles.sphere_part.resize(n);
  tiles.sphere_x.resize(n);
  tiles.sphere_y.resize(n);
  run_chunks(runner, n, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const std::uint32_t ix = tile_of(positions[i].x(), box.lx, grid.nx);
      const std::uint32_t iy = tile_of(positions[i].y(), box.ly, grid.ny);
      tiles.sphere_x[i] = ix;
      tiles.sphere_y[i] = iy;
      tiles.sphere_part[i] = tiles.part_of_tile[iy * grid.nx + ix];
    }
  });
}

std::vector<std::uint8_t> parts_of_rank(const StepTiles& tiles, int rank, int ranks) {
  std::vector<std::uint8_t> solved(tiles.parts(), 0);
  const TileGrid& grid = tiles.grid;
  for (std::uint32_t j = strip_start(rank, grid.ny, ranks);
       j < strip_start(rank + 1, grid.ny, ranks); ++j) {
    for (std::uint32_t i = 0; i < grid.nx; ++i) solved[tiles.part_of_tile[j * grid.nx + i]] = 1;
  }
  for (std::uint32_t p = tiles.phase_parts[kTilePhases]; p < tiles.parts(); ++p) solved[p] = 1;
  return solved;
}

std::vector<int> sphere_ranks(const std::vector<Vec3>& positions, const PeriodicBox& box,
                              double max_radius, double width, int ranks) {
  const TileGrid grid = tile_grid(box, max_radius, width);
  std::vector<int> row_rank(grid.ny, 0);
  for (int r = 0; r < ranks; ++r) {
    for (std::uint32_t j = strip_start(r, grid.ny, ranks); j < strip_start(r + 1, grid.ny, ranks);
         ++j) {
      row_rank[j] = r;
    }
  }
  std::vector<int> rank_of(positions.size(), 0);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    Vec3 at = positions[i];
    box.wrap(at);
    rank_of[i] = row_rank[tile_of(at.y(), box.ly, grid.ny)];
  }
  return rank_of;
}

}  // namespace cdpowder
