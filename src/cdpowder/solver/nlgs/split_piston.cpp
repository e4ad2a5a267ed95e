// split_piston.cpp — the piston's contacts grouped by tile, their split problems, and a pass
// over them (split_piston.hpp).
#include "cdpowder/solver/nlgs/split_piston.hpp"

#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/solver/nlgs/group_by_part.hpp"
#include "cdpowder/solver/nlgs/tile_ranks.hpp"
#include "cdpowder/solver/nlgs/visit_contact.hpp"

#include <cstddef>
#include <span>

namespace cdpowder {

void group_piston_contacts(const Contacts& contacts, const StepTiles* tiles, SplitPiston& split) {
  split.walls.clear();
  split.piece_start.assign(1, 0);
  split.strip_order.clear();
  if (tiles == nullptr || !tiles->tiled()) return;
  // a counting sort by tile, storage order within a tile; the other walls last, left out
  const std::uint32_t tile_count = tiles->grid.tiles();
  const std::vector<std::uint32_t>& start = split.tile_start;
  group_by_part(
      contacts.walls.size(), tile_count + 1,
      [&](std::size_t k) -> std::size_t {
        const WallProblem& w = contacts.walls[k];
        return w.wall == WallKind::Piston ? tiles->sphere_part[w.sphere] : tile_count;
      },
      split.tile_start, split.tile_next, split.wall_order);
  split.walls.assign(split.wall_order.begin(), split.wall_order.begin() + start[tile_count]);
  // the tiles with piston contacts are the pieces (in part order), handed out row by row
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  split.piece_of_part.assign(tile_count, kNone);
  for (std::uint32_t t = 0; t < tile_count; ++t) {
    if (start[t + 1] > start[t]) {
      split.piece_of_part[t] = split.pieces();
      split.piece_start.push_back(start[t + 1]);
    }
  }
  for (const std::uint32_t part : tiles->part_of_tile) {
    if (split.piece_of_part[part] != kNone) split.strip_order.push_back(split.piece_of_part[part]);
  }
}

namespace {

/// Contact w's problem with the piston's mass split among n tiles: the normal block of W is
/// Δt/m of the sphere plus the piston's n Δt/M_P along n = −e_z (the sphere's lever −R n turns
/// nothing about n), as the build forms it with Δt/M_P.
WallProblem with_split_mass(const WallProblem& w, const VelocityCache& velocities, double n) {
  WallProblem split = w;
  split.wall_response = n * w.wall_response;
  const double dt_w_n = velocities.spheres[w.sphere].dt_inverse_mass + split.wall_response;
  split.inv_dt_w_n = dt_w_n > 0.0 ? 1.0 / dt_w_n : 0.0;
  return split;
}

}  // namespace

PassSums run_split_piston(Contacts& contacts, VelocityCache& velocities, const SplitPiston& split,
                          PieceRunner* pieces, TileRanks* ranks) {
  const double start_velocity = velocities.piston_velocity;
  const auto n = static_cast<double>(split.pieces());
  split.results.resize(split.pieces());
  const auto solve_piece = [&](std::uint32_t p) {
    SplitPiston::PieceResult& result = split.results[p];
    result.sums = PassSums{};
    double velocity = start_velocity;  // V_t, this tile's copy of V_P
    for (std::uint32_t j = split.piece_start[p]; j < split.piece_start[p + 1]; ++j) {
      const WallProblem w = with_split_mass(contacts.walls[split.walls[j]], velocities, n);
      ContactAction& action = contacts.wall_actions[split.walls[j]];
      const VisitChange change = solve_wall(w, action, velocities.spheres[w.sphere], velocity);
      add_visit(result.sums, change, action.normal_force, w.cohesion);
    }
    result.velocity = velocity;
  };
  if (ranks != nullptr && ranks->active()) {
    // this rank's tiles, then every piece's result from the rank that solved it
    const std::span<const std::uint32_t> mine = ranks->own_piston_pieces();
    run_pieces(pieces, static_cast<std::uint32_t>(mine.size()),
               [&](std::uint32_t i) { solve_piece(mine[i]); });
    ranks->after_piston(velocities);
    ranks->share_piston_pieces(split.results);
  } else {
    run_pieces_in(pieces, split.strip_order, split.pieces(), solve_piece);
  }
  // the tiles' impulses on the piston, added in tile order: ΔV_P = Σ_t (V_t − V_P)/n
  double change = 0.0;
  PassSums sums;
  for (const SplitPiston::PieceResult& result : split.results) {
    change += (result.velocity - start_velocity) / n;
    sums.add_part(result.sums);
  }
  velocities.piston_velocity = start_velocity + change;
  return sums;
}

}  // namespace cdpowder
