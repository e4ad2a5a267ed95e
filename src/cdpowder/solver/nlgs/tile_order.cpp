// tile_order.cpp — the cache's records in tile order and back (tile_order.hpp).
#include "cdpowder/solver/nlgs/tile_order.hpp"

#include "cdpowder/solver/nlgs/group_by_part.hpp"

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
  // by tile (parts 0 … T − 1), index order within a tile
  group_by_part(
      n, tiles.grid.tiles(), [&](std::size_t i) { return tiles.sphere_part[i]; }, order.part_start,
      order.next, order.sphere_at);
  order.place_of.resize(n);
  for (std::size_t place = 0; place < n; ++place) {
    order.place_of[order.sphere_at[place]] = static_cast<BodyIndex>(place);
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
