// tile_order.cpp — the cache's records in tile order and back (tile_order.hpp).
#include "cdpowder/solver/nlgs/tile_order.hpp"

#include <cstddef>
#include <cstdint>

namespace cdpowder {

namespace {

/// Every sphere row of the batches (offsets in doubles) renamed through `name`.
void rename_rows(ColouredPass& pass, const std::vector<BodyIndex>& name) {
  const auto renamed = [&](std::uint32_t row) {
    return name[row / kRecordDoubles] * kRecordDoubles;
  };
  for (BatchPair& pair : pass.batch_pairs) {
    for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
      pair.a_row[lane] = renamed(pair.a_row[lane]);
      pair.b_row[lane] = renamed(pair.b_row[lane]);
    }
  }
  for (WallBatchPair& pair : pass.wall_batch_pairs) {
    for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
      pair.s_row[lane] = renamed(pair.s_row[lane]);
    }
  }
}

/// The spheres of the solve's contacts renamed through `name`.
void rename_spheres(Contacts& contacts, ColouredPass& pass, const std::vector<BodyIndex>& name) {
  for (PairProblem& p : contacts.pairs) {
    p.a = name[p.a];
    p.b = name[p.b];
  }
  for (WallProblem& w : contacts.walls) w.sphere = name[w.sphere];
  rename_rows(pass, name);
}

}  // namespace

void enter_tile_order(const StepTiles& tiles, Contacts& contacts, VelocityCache& velocities,
                      ColouredPass& pass, TileOrder& order) {
  const std::size_t n = velocities.spheres.size();
  const std::uint32_t tile_count = tiles.grid.tiles();
  // a counting sort by tile (parts 0 … T − 1), index order within a tile
  order.part_start.assign(tile_count + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++order.part_start[tiles.sphere_part[i] + 1];
  for (std::uint32_t t = 0; t < tile_count; ++t) {
    order.part_start[t + 1] += order.part_start[t];
  }
  order.sphere_at.resize(n);
  order.place_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t place = order.part_start[tiles.sphere_part[i]]++;
    order.sphere_at[place] = static_cast<BodyIndex>(i);
    order.place_of[i] = static_cast<BodyIndex>(place);
  }
  order.scratch.resize(n);
  for (std::size_t place = 0; place < n; ++place) {
    order.scratch[place] = velocities.spheres[order.sphere_at[place]];
  }
  velocities.spheres.swap(order.scratch);
  rename_spheres(contacts, pass, order.place_of);
  order.active = true;
}

void leave_tile_order(Contacts& contacts, VelocityCache& velocities, ColouredPass& pass,
                      TileOrder& order) {
  if (!order.active) return;
  const std::size_t n = velocities.spheres.size();
  for (std::size_t place = 0; place < n; ++place) {
    order.scratch[order.sphere_at[place]] = velocities.spheres[place];
  }
  velocities.spheres.swap(order.scratch);
  rename_spheres(contacts, pass, order.sphere_at);
  order.active = false;
}

}  // namespace cdpowder
