// tiles.hpp — the fixed grid of x–y tiles a step's passes are cut into, so that threads (and
// later ranks) solve tiles side by side (docs/architecture.md, "Scale: one tile grid").
// The grid is a function of the cell and the largest radius alone, never of the thread count:
// the visiting order, and with it every result, is the same on any number of threads.
//
// - A sphere belongs to the tile of its centre at the start of the step.
// - A pair contact belongs to the tile of its "lower-left" sphere per axis, so it touches the
//   2 × 2 block of tiles starting at its own. A pair whose spheres are not in one such block
//   (spheres larger than a tile allows) goes to the hub.
// - A bottom-wall contact belongs to its sphere's tile. The piston's contacts share the
//   piston's velocity: they form the hub, solved after the tiles.
// - The tiles are coloured in a 2 × 2 checkerboard (i mod 2, j mod 2). Two tiles of one colour
//   are two tiles apart, so their blocks are disjoint: a phase's tiles share no sphere and are
//   solved at once. A pass is the four phases and the hub, in an order drawn per step
//   (ColouredPass::slot_order).
//
// Parts number the tiles in pass order (phase, then tile index), the hub last: the pass
// visits parts 0, 1, …, and a part's contacts are coloured and batched on their own.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/periodic_box.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace cdpowder {

/// Below this many sphere–sphere contacts a step is one part (no tiles, no hub): a pass then
/// takes a few microseconds, no more than handing work to another thread costs.
inline constexpr std::size_t kMinPairsToTile = 256;

/// The width a tile aims at, in largest radii: a contact spans 2 R_max plus a small gap, so a
/// tile holds every contact in its 2 × 2 block with room to spare. Narrower tiles give more of
/// them to share among threads but colour into smaller batches: at 16 240 spheres (a 100 R
/// cell) tiles of 8.3 R made a run on one thread about 5 % slower than tiles of 12.5 R, and both
/// shared well between two threads (docs/lab/2026-11-29-tiles.md). The paper's 25 R cell gets
/// 2 × 2 tiles of 12.5 R.
inline constexpr double kTileWidthRadii = 12.0;

/// Colour phases of a pass: the 2 × 2 checkerboard.
inline constexpr std::size_t kTilePhases = 4;

/// Tiles along each periodic direction: even (the checkerboard wraps), or 1 where the cell is
/// narrower than two tiles.
struct TileGrid {
  std::uint32_t nx = 1;
  std::uint32_t ny = 1;

  [[nodiscard]] std::uint32_t tiles() const { return nx * ny; }
};

/// The grid of `box` for tiles of `width` (0: kTileWidthRadii × `max_radius`).
TileGrid tile_grid(const PeriodicBox& box, double max_radius, double width);

/// The first tile row of rank `rank`'s strip when `ranks` ranks share `ny` rows: rank r solves
/// rows [strip_start(r), strip_start(r + 1)) (solver/nlgs/tile_ranks.hpp), none where ny < ranks
/// leaves it none.
[[nodiscard]] inline std::uint32_t strip_start(int rank, std::uint32_t ny, int ranks) {
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(rank) * ny /
                                    static_cast<std::uint64_t>(ranks));
}

/// Each sphere's rank among `ranks`: the rank whose strip holds the sphere's tile row in the grid
/// of tile_grid(box, max_radius, width). The piece of the run's VTK files that rank writes
/// (run/run_folder.hpp, write_vtk_pieces).
std::vector<int> sphere_ranks(const std::vector<Vec3>& positions, const PeriodicBox& box,
                              double max_radius, double width, int ranks);

/// A step's tiling: each sphere's part, the parts of each phase and the hub.
struct StepTiles {
  TileGrid grid;
  /// each sphere's tile as its part (pass order); empty: the step is not tiled (one part)
  std::vector<std::uint32_t> sphere_part;
  /// the tile coordinates of each sphere (ix, iy), for the owner of a pair
  std::vector<std::uint32_t> sphere_x;
  std::vector<std::uint32_t> sphere_y;
  /// tile index iy·nx + ix → part
  std::vector<std::uint32_t> part_of_tile;
  /// phase f is parts [phase_parts[f], phase_parts[f + 1]); the hub is part phase_parts[4]
  std::array<std::uint32_t, kTilePhases + 1> phase_parts{};

  [[nodiscard]] bool tiled() const { return !sphere_part.empty(); }

  /// Parts of a pass: the tiles and the hub, or one when not tiled.
  [[nodiscard]] std::uint32_t parts() const { return tiled() ? grid.tiles() + 1 : 1; }

  /// Whether a phase has two tiles or more to share among threads. The paper's 25 R cell has
  /// one tile a phase: its passes gain nothing from threads (two lost it 3 %).
  [[nodiscard]] bool tiles_to_share() const {
    for (std::size_t phase = 0; tiled() && phase < kTilePhases; ++phase) {
      if (phase_parts[phase + 1] - phase_parts[phase] >= 2) return true;
    }
    return false;
  }

  /// The hub's part (tiled steps only).
  [[nodiscard]] std::uint32_t hub() const { return grid.tiles(); }

  /// The part of pair p: its lower-left sphere's tile, or the hub.
  [[nodiscard]] std::uint32_t pair_part(const PairProblem& p) const;

  /// The part of wall contact w: its sphere's tile for the bottom wall, the hub for the piston.
  [[nodiscard]] std::uint32_t wall_part(const WallProblem& w) const {
    return w.wall == WallKind::Piston ? hub() : sphere_part[w.sphere];
  }
};

/// One flag a part of `tiles`: set for the parts rank `rank` of `ranks` solves, the tiles of its
/// strip of rows and the hub's (every rank solves the hub).
std::vector<std::uint8_t> parts_of_rank(const StepTiles& tiles, int rank, int ranks);

/// Sets the step's tiling from the spheres' positions (wrapped into the cell) and the grid of
/// tile_grid(box, max_radius, width): not tiled below kMinPairsToTile pairs or with a grid of
/// one tile. The spheres in pieces on `runner` when given (run_chunks).
void assign_tiles(const std::vector<Vec3>& positions, const PeriodicBox& box, double max_radius,
                  double width, const Contacts& contacts, StepTiles& tiles,
                  PieceRunner* runner = nullptr);

}  // namespace cdpowder
