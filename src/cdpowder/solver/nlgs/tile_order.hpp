// tile_order.hpp — the velocity cache in tile order for the passes of a tiled step
// (tiles.hpp). The spheres are numbered as the run made them (a deposit's order, close to
// height order), so a tile's spheres lie all over the cache: every thread would stream through
// all of it, and two threads share every cache line's neighbourhood. For the passes the records
// go tile by tile (each tile's in index order), and the contacts of the solve (the pairs' and
// walls' records, the batches' rows) name the spheres by their place. The arithmetic of every
// contact is the same, so the bits are those of the cache in index order; what changes is which
// memory a tile touches: its own spheres, contiguous, and its neighbours' at the edges.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/solver/nlgs/coloured_pass.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"

#include <vector>

namespace cdpowder {

/// The places of a tiled step's spheres, and scratch; kept from step to step.
struct TileOrder {
  std::vector<BodyIndex> sphere_at;  ///< place → sphere
  std::vector<BodyIndex> place_of;   ///< sphere → place
  /// the records of part p (a tile, p < the tile count) are places
  /// [part_start[p], part_start[p + 1])
  std::vector<std::uint32_t> part_start;
  std::vector<std::uint32_t> next;      ///< scratch of the counting sort
  std::vector<SphereVelocity> scratch;  ///< the other copy of the records
  bool active = false;                  ///< between enter_tile_order and leave_tile_order
};

/// Puts the cache's records in tile order and renames the spheres in the solve's contacts
/// (contacts.pairs, contacts.walls, the batches' rows of `pass`) to their places; the moves
/// and renamings in pieces on `runner` when there is one (core/pieces.hpp, run_chunks).
void enter_tile_order(const StepTiles& tiles, Contacts& contacts, VelocityCache& velocities,
                      ColouredPass& pass, TileOrder& order, PieceRunner* runner = nullptr);

/// Undoes enter_tile_order (the records back in index order, the spheres' own names back);
/// nothing when it is not active.
void leave_tile_order(Contacts& contacts, VelocityCache& velocities, ColouredPass& pass,
                      TileOrder& order, PieceRunner* runner = nullptr);

}  // namespace cdpowder
