// split_piston.hpp — the piston's contacts of a tiled step, solved tile by tile with the
// piston's mass split among the tiles that touch it (docs/architecture.md, "The piston, a
// hub"; physics.md §7.1). The piston couples every one of its contacts through one velocity
// V_P, so solved one by one they are one long sequential part of every pass; at 10⁶ spheres
// the piston touches 10⁴–10⁵ of them. Here each tile t that has piston contacts solves its own
// with a copy V_t of V_P, taken at the hub's start, and the piston's inverse mass multiplied
// by n, the number of such tiles (the mass splitting of non-smooth domain decomposition and of
// parallel rigid-body solvers). The tiles' impulses on the piston are then added in tile order
// and V_P moves once: V_P ← V_P + Σ_t (V_t − V_P)/n. With one tile this is the sequential
// update. The tiles share no sphere, so they run side by side, and the result does not depend
// on the threads.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/index.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

class TileRanks;  // tile_ranks.hpp

struct SplitPiston {
  /// the piston's wall contacts (indices into Contacts::walls), tile by tile in tile order,
  /// each tile's in storage order
  std::vector<ContactIndex> walls;
  /// piece p (the p-th tile with piston contacts): walls[piece_start[p], piece_start[p + 1])
  std::vector<std::uint32_t> piece_start{0};

  /// each piece's sums and V_t of the last pass, on cache lines of their own
  struct alignas(64) PieceResult {
    PassSums sums;
    double velocity = 0.0;
  };

  mutable std::vector<PieceResult> results;
  /// the pieces in the order of their tiles, row by row: the order the threads are handed them
  /// in, so a thread takes the rows of tiles it solves in the phases (ColouredPass::strip_order);
  /// their sums are still added in piece order
  std::vector<std::uint32_t> strip_order;
  /// scratch of group_piston_contacts (kept from step to step)
  std::vector<std::uint32_t> tile_start, tile_next, piece_of_part;
  std::vector<ContactIndex> wall_order;

  [[nodiscard]] std::uint32_t pieces() const {
    return static_cast<std::uint32_t>(piece_start.size() - 1);
  }

  /// Whether the step's piston contacts are split (a tiled step with any).
  [[nodiscard]] bool active() const { return !walls.empty(); }
};

/// Groups the piston's contacts of a tiled step by their sphere's tile (`tiles` in the
/// spheres' own indices); for a step that is not tiled (null), none.
void group_piston_contacts(const Contacts& contacts, const StepTiles* tiles, SplitPiston& split);

/// One pass over the pieces (side by side on `pieces` when given), then V_P moved once;
/// returns the pieces' sums added in piece order. Each visit solves its contact's problem with
/// the split mass: the piston's response n Δt/M_P and the normal block 1/(Δt w_n) with it.
/// With `ranks` active (tile_ranks.hpp) this rank solves its own tiles' pieces, and every
/// piece's sums and V_t go to every rank before V_P moves: the same bits on every rank.
PassSums run_split_piston(Contacts& contacts, VelocityCache& velocities, const SplitPiston& split,
                          PieceRunner* pieces, TileRanks* ranks = nullptr);

}  // namespace cdpowder
