// tile_order.cpp — the cache's records in tile order and back (tile_order.hpp).
#include "cdpowder/solver/nlgs/tile_order.hpp"

#include "cdpowder/solver/nlgs/group_by_part.hpp"

#include <cstddef>
#include <cstdint>

namespace cdpowder {

namespace {

/// Every sphere row of the batches (offsets in doubles) renamed through `name`.
void rename_rows(ColouredPass& pass, const std::vector<BodyIndex>& name, PieceRunner* runner) {
  const auto renamed = [&](std::uint32_t row) {
    return name[row / kRecordDoubles] * kRecordDoubles;
  };
  // a piece of batches renames as many pairs as a piece of pairs
  run_chunks(
      runner, pass.batch_pairs.size(),
      [&](std::size_t first, std::size_t last) {
        for (std::size_t k = first; k < last; ++k) {
          BatchPair& pair = pass.batch_pairs[k];
          for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
            pair.a_row[lane] = renamed(pair.a_row[lane]);
            pair.b_row[lane] = renamed(pair.b_row[lane]);
          }
        }
      },
      kChunkIndices / static_cast<std::size_t>(kPairLanes));
  for (WallBatchPair& pair : pass.wall_batch_pairs) {
    for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
      pair.s_row[lane] = renamed(pair.s_row[lane]);
    }
  }
}

/// The spheres of the solve's contacts renamed through `name`, in pieces on `runner`.
void rename_spheres(Contacts& contacts, ColouredPass& pass, const std::vector<BodyIndex>& name,
                    PieceRunner* runner) {
  run_chunks(runner, contacts.pairs.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      PairProblem& p = contacts.pairs[k];
      p.a = name[p.a];
      p.b = name[p.b];
    }
  });
  for (WallProblem& w : contacts.walls) w.sphere = name[w.sphere];
  rename_rows(pass, name, runner);
}

}  // namespace

void enter_tile_order(const StepTiles& tiles, Contacts& contacts, VelocityCache& velocities,
                      ColouredPass& pass, TileOrder& order, PieceRunner* runner) {
  const std::size_t n = velocities.spheres.size();
  // by tile (parts 0 … T − 1), index order within a tile; a counting sort in pieces
  group_by_part(
      runner, n, tiles.grid.tiles(), [&](std::size_t i) { return tiles.sphere_part[i]; },
      order.part_start, order.next, order.sphere_at);
  order.place_of.resize(n);
  order.scratch.resize(n);
  // each place written once: a permutation's inverse and a gather, in pieces
  run_chunks(runner, n, [&](std::size_t first, std::size_t last) {
    for (std::size_t place = first; place < last; ++place) {
      order.place_of[order.sphere_at[place]] = static_cast<BodyIndex>(place);
      order.scratch[place] = velocities.spheres[order.sphere_at[place]];
    }
  });
  velocities.spheres.swap(order.scratch);
  rename_spheres(contacts, pass, order.place_of, runner);
  order.active = true;
}

void leave_tile_order(Contacts& contacts, VelocityCache& velocities, ColouredPass& pass,
                      TileOrder& order, PieceRunner* runner) {
  if (!order.active) return;
  const std::size_t n = velocities.spheres.size();
  run_chunks(runner, n, [&](std::size_t first, std::size_t last) {
    for (std::size_t place = first; place < last; ++place) {
      order.scratch[order.sphere_at[place]] = velocities.spheres[place];
    }
  });
  velocities.spheres.swap(order.scratch);
  rename_spheres(contacts, pass, order.sphere_at, runner);
  order.active = false;
}

}  // namespace cdpowder
