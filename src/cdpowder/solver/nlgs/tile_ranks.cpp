// tile_ranks.cpp — the tiles of a step's passes shared among MPI ranks (tile_ranks.hpp).
#include "cdpowder/solver/nlgs/tile_ranks.hpp"

#include "cdpowder/solver/nlgs/coloured_pass.hpp"
#include "cdpowder/solver/nlgs/tile_order.hpp"

#include <algorithm>
#include <iterator>
#include <type_traits>
#include <utility>

namespace cdpowder {

namespace {

// The records travel as the bytes of typed buffers (MPI copies bytes): eight doubles each.
static_assert(std::is_standard_layout_v<SphereVelocity> && sizeof(SphereVelocity) == 64);
static_assert(std::is_standard_layout_v<ContactAction> && sizeof(ContactAction) == 64);
static_assert(std::is_trivially_copyable_v<PassSums>);

/// The bytes of a typed buffer, for MPI.
template <typename T>
std::span<std::byte> bytes_of(std::vector<T>& buffer) {
  return std::as_writable_bytes(std::span<T>(buffer));
}

/// Every rank's `mine` into `all`, in rank order; `items_of(r)` is rank r's number of items,
/// which every rank knows from the plan. `counts` is scratch.
template <typename T, typename ItemsOf>
void gather_items(std::vector<T>& mine, std::vector<T>& all, std::vector<int>& counts, int ranks,
                  const ItemsOf& items_of) {
  counts.assign(static_cast<std::size_t>(ranks), 0);
  std::size_t total = 0;
  for (int r = 0; r < ranks; ++r) {
    const std::size_t items = items_of(r);
    counts[static_cast<std::size_t>(r)] = static_cast<int>(items * sizeof(T));
    total += items;
  }
  all.resize(total);
  gather_from_all_ranks(bytes_of(mine), bytes_of(all), counts);
}

}  // namespace

void TileRanks::plan(const StepTiles* tiles, const ColouredPass& pass, const TileOrder& order,
                     const Contacts& contacts) {
  ranks_ = rank_count();
  rank_ = this_rank();
  active_ = ranks_ > 1 && tiles != nullptr && tiles->tiled();
  shared_ = true;
  actions_shared_ = true;
  if (!active_) return;  // the caller solves every part
  grid_ = tiles->grid;
  const std::uint32_t nx = grid_.nx;
  const std::uint32_t ny = grid_.ny;
  const std::uint32_t tile_count = grid_.tiles();
  const std::size_t parts = pass.parts();

  // the places of each tile's spheres: stored part by part (tile_order.hpp)
  part_start_ = order.part_start;

  // strips of whole rows: rank r solves rows [r ny / P, (r + 1) ny / P) (none when ny < P)
  row_parts_.assign(tiles->part_of_tile.begin(), tiles->part_of_tile.end());
  row_owner_.assign(ny, 0);
  rank_rows_.assign(static_cast<std::size_t>(ranks_), {});
  for (int r = 0; r < ranks_; ++r) {
    for (std::uint32_t j = strip_start(r, ny, ranks_); j < strip_start(r + 1, ny, ranks_); ++j) {
      row_owner_[j] = r;
      rank_rows_[static_cast<std::size_t>(r)].push_back(j);
    }
  }
  std::vector<std::uint32_t> part_row(parts, 0);
  for (std::uint32_t t = 0; t < tile_count; ++t) part_row[tiles->part_of_tile[t]] = t / nx;
  rank_parts_.assign(static_cast<std::size_t>(ranks_), {});
  for (std::uint32_t p = 0; p < pass.phase_parts[kTilePhases]; ++p) {
    rank_parts_[static_cast<std::size_t>(row_owner_[part_row[p]])].push_back(p);
  }

  plan_hub(pass, contacts, part_row);
  plan_piston(pass, contacts, part_row);

  for (std::size_t f = 0; f < kTilePhases; ++f) {
    mine_[f].clear();
    for (std::uint32_t p = pass.phase_parts[f]; p < pass.phase_parts[f + 1]; ++p) {
      if (row_owner_[part_row[p]] == rank_) mine_[f].push_back(p);
    }
  }
  plan_phase_messages(pass, contacts, part_row);
}

void TileRanks::plan_phase_messages(const ColouredPass& pass, const Contacts& contacts,
                                    const std::vector<std::uint32_t>& part_row) {
  for (std::size_t f = 0; f < kTilePhases; ++f) {
    sends_[f].clear();
    receives_[f].clear();
  }
  const std::vector<std::uint32_t>& rows = rank_rows_[static_cast<std::size_t>(rank_)];
  if (rows.empty()) return;  // a rank without rows (ny < P) solves no tile
  const std::uint32_t ny = grid_.ny;
  const std::uint32_t first = rows.front();
  const std::uint32_t last = rows.back();
  const std::uint32_t below = (first + ny - 1) % ny;  // its tiles write my first row
  const std::uint32_t ghost = (last + 1) % ny;        // my last row's tiles write it
  const int lower = row_owner_[below];
  const int upper = row_owner_[ghost];
  marks_.assign(part_start_.back(), 0);
  const auto both = [](const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> out;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;
  };
  // A rank reads a sphere of its ghost row only through its own tiles' contacts. Of my first
  // row: what my tiles write (the lower rank reads those its tiles touch) and what the lower
  // rank's write. Of my ghost row: what my tiles write (all of which its owner keeps) and what
  // its owner's write (I read those mine touch).
  PhaseWrites mine_first;
  PhaseWrites lower_first;
  PhaseWrites mine_ghost;
  PhaseWrites upper_ghost;
  if (lower != rank_) {
    mine_first = phase_writes(pass, contacts, part_row, first, first);
    lower_first = phase_writes(pass, contacts, part_row, below, first);
  }
  if (upper != rank_) {
    mine_ghost = phase_writes(pass, contacts, part_row, last, ghost);
    upper_ghost = phase_writes(pass, contacts, part_row, ghost, ghost);
  }
  for (std::size_t f = 0; f < kTilePhases; ++f) {
    if (lower != rank_) {
      add_places(sends_[f], lower, both(mine_first[f], lower_first[kTilePhases]));
      add_places(receives_[f], lower, lower_first[f]);
    }
    if (upper != rank_) {
      add_places(sends_[f], upper, mine_ghost[f]);
      add_places(receives_[f], upper, both(upper_ghost[f], mine_ghost[kTilePhases]));
    }
    for (auto* list : {&sends_[f], &receives_[f]}) {
      // the two halves to one peer (two ranks on a periodic cell) as one message, in the same
      // order on both sides
      for (PlaceMessage& m : *list) {
        std::sort(m.places.begin(), m.places.end());
        m.places.erase(std::unique(m.places.begin(), m.places.end()), m.places.end());
        m.buffer.resize(m.places.size());
      }
      std::erase_if(*list, [](const PlaceMessage& m) { return m.places.empty(); });
    }
  }
}

TileRanks::PhaseWrites TileRanks::phase_writes(const ColouredPass& pass, const Contacts& contacts,
                                               const std::vector<std::uint32_t>& part_row,
                                               std::uint32_t tile_row, std::uint32_t row) {
  // each sphere the row's tiles write marked with its phases (marks_, all clear on entry and
  // on return), then the row's spheres read in place order
  std::size_t phase = 0;
  touched_.clear();
  for (std::uint32_t p = 0; p < pass.phase_parts[kTilePhases]; ++p) {
    while (p >= pass.phase_parts[phase + 1]) ++phase;
    if (part_row[p] != tile_row) continue;
    const std::size_t before = touched_.size();
    append_part_spheres(pass, contacts, p, touched_);
    for (std::size_t i = before; i < touched_.size(); ++i) {
      marks_[touched_[i]] |= static_cast<std::uint8_t>(1U << phase);
    }
  }
  // the row's tiles in place order: each one range of places (tile_order.hpp)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges;
  for (std::uint32_t i = 0; i < grid_.nx; ++i) {
    const std::uint32_t part = row_parts_[row * grid_.nx + i];
    ranges.emplace_back(part_start_[part], part_start_[part + 1]);
  }
  std::sort(ranges.begin(), ranges.end());
  PhaseWrites places;
  for (const auto& [from, to] : ranges) {
    for (std::uint32_t place = from; place < to; ++place) {
      const std::uint8_t mark = marks_[place];
      if (mark == 0) continue;
      for (std::size_t f = 0; f < kTilePhases; ++f) {
        if ((mark >> f & 1U) != 0) places[f].push_back(place);
      }
      places[kTilePhases].push_back(place);
    }
  }
  for (const std::uint32_t place : touched_) marks_[place] = 0;
  return places;
}

void TileRanks::add_places(std::vector<PlaceMessage>& list, int peer,
                           const std::vector<std::uint32_t>& places) {
  auto message =
      std::find_if(list.begin(), list.end(), [&](const PlaceMessage& m) { return m.peer == peer; });
  if (message == list.end()) message = list.insert(list.end(), PlaceMessage{peer, {}, {}});
  message->places.insert(message->places.end(), places.begin(), places.end());
}

void TileRanks::append_part_spheres(const ColouredPass& pass, const Contacts& contacts,
                                    std::uint32_t part, std::vector<std::uint32_t>& places) {
  const std::size_t pairs = contacts.pairs.size();
  const auto add_pair = [&](ContactIndex k) {
    const PairProblem& p = pass.pair_record(contacts, k);
    places.push_back(p.a);
    places.push_back(p.b);
  };
  const PairColouring& colouring = pass.colouring;
  for (std::uint32_t k = colouring.first_member(part); k < colouring.first_member(part + 1); ++k) {
    add_pair(k);
  }
  // the overflow pairs and walls of a pass, and those of a mixing (tile_solve.cpp)
  for (std::uint32_t j = pass.part_sequential[part]; j < pass.part_sequential[part + 1]; ++j) {
    const ContactIndex k = pass.sequential[j];
    if (k < pairs) {
      add_pair(k);
    } else {
      places.push_back(contacts.walls[k - pairs].sphere);
    }
  }
  const std::size_t overflow = colouring.first_member(pass.parts());
  for (std::size_t k = overflow + colouring.part_overflow[part];
       k < overflow + colouring.part_overflow[part + 1]; ++k) {
    add_pair(static_cast<ContactIndex>(k));
  }
  for (std::uint32_t i = pass.mixing_wall_start[part]; i < pass.mixing_wall_start[part + 1]; ++i) {
    places.push_back(contacts.walls[pass.mixing_walls[i]].sphere);
  }
}

void TileRanks::plan_hub(const ColouredPass& pass, const Contacts& contacts,
                         const std::vector<std::uint32_t>& part_row) {
  // the places of the hub's spheres: its parts' pairs and sequential groups
  std::vector<std::uint32_t> places;
  const std::size_t pairs = contacts.pairs.size();
  const auto add_pair = [&](const PairProblem& p) {
    places.push_back(p.a);
    places.push_back(p.b);
  };
  for (std::size_t part = pass.phase_parts[kTilePhases]; part < pass.parts(); ++part) {
    for (std::uint32_t k = pass.colouring.first_member(part);
         k < pass.colouring.first_member(part + 1); ++k) {
      add_pair(pass.pair_record(contacts, k));
    }
    for (std::uint32_t j = pass.part_sequential[part]; j < pass.part_sequential[part + 1]; ++j) {
      const ContactIndex k = pass.sequential[j];
      if (k < pairs) {
        add_pair(pass.pair_record(contacts, k));
      } else {
        places.push_back(contacts.walls[k - pairs].sphere);
      }
    }
  }
  std::sort(places.begin(), places.end());
  places.erase(std::unique(places.begin(), places.end()), places.end());
  // each to the rank whose rows hold it: place → part (part_start_) → row → owner
  rank_hub_places_.assign(static_cast<std::size_t>(ranks_), {});
  for (const std::uint32_t place : places) {
    const int owner = row_owner_[part_row[part_of_place(place)]];
    rank_hub_places_[static_cast<std::size_t>(owner)].push_back(place);
  }
}

void TileRanks::plan_piston(const ColouredPass& pass, const Contacts& contacts,
                            const std::vector<std::uint32_t>& part_row) {
  // a piece's contacts are those of one tile: its first contact's sphere names it
  const SplitPiston& split = pass.split_piston;
  rank_piston_pieces_.assign(static_cast<std::size_t>(ranks_), {});
  piston_sends_.clear();
  piston_receives_.clear();
  const std::uint32_t ny = grid_.ny;
  for (std::uint32_t p = 0; p < split.pieces(); ++p) {
    const std::uint32_t place = contacts.walls[split.walls[split.piece_start[p]]].sphere;
    const std::uint32_t row = part_row[part_of_place(place)];
    const int owner = row_owner_[row];
    rank_piston_pieces_[static_cast<std::size_t>(owner)].push_back(p);
    // the piece's spheres to the rank for which their row is the ghost row
    const int holder = row_owner_[(row + ny - 1) % ny];
    if (holder == owner || (owner != rank_ && holder != rank_)) continue;
    std::vector<PlaceMessage>& list = owner == rank_ ? piston_sends_ : piston_receives_;
    const int peer = owner == rank_ ? holder : owner;
    auto message = std::find_if(list.begin(), list.end(),
                                [&](const PlaceMessage& m) { return m.peer == peer; });
    if (message == list.end()) message = list.insert(list.end(), PlaceMessage{peer, {}, {}});
    for (std::uint32_t j = split.piece_start[p]; j < split.piece_start[p + 1]; ++j) {
      message->places.push_back(contacts.walls[split.walls[j]].sphere);
    }
  }
  for (auto* list : {&piston_sends_, &piston_receives_}) {
    for (PlaceMessage& m : *list) m.buffer.resize(m.places.size());
  }
}

void TileRanks::after_piston(VelocityCache& velocities) {
  if (!active_) return;
  shared_ = false;  // the pieces' spheres moved on their own ranks
  exchange_places(piston_sends_, piston_receives_, static_cast<int>(kTilePhases), velocities);
}

std::uint32_t TileRanks::part_of_place(std::uint32_t place) const {
  const auto after = std::upper_bound(part_start_.begin(), part_start_.end(), place);
  return static_cast<std::uint32_t>(after - part_start_.begin() - 1);
}

void TileRanks::share_hub_records(VelocityCache& velocities) {
  if (!active_ || shared_) return;
  share_bytes(bytes_of(velocities.spheres), sizeof(SphereVelocity), rank_hub_places_);
}

std::size_t TileRanks::row_records(std::span<const std::uint32_t> rows) const {
  std::size_t records = 0;
  for (const std::uint32_t row : rows) {
    for (std::uint32_t i = 0; i < grid_.nx; ++i) {
      const std::uint32_t part = row_parts_[row * grid_.nx + i];
      records += part_start_[part + 1] - part_start_[part];
    }
  }
  return records;
}

void TileRanks::pack_rows(std::span<const std::uint32_t> rows, const VelocityCache& velocities,
                          SphereVelocity* out) const {
  for (const std::uint32_t row : rows) {
    for (std::uint32_t i = 0; i < grid_.nx; ++i) {
      const std::uint32_t part = row_parts_[row * grid_.nx + i];
      out = std::copy(velocities.spheres.begin() + part_start_[part],
                      velocities.spheres.begin() + part_start_[part + 1], out);
    }
  }
}

void TileRanks::unpack_rows(std::span<const std::uint32_t> rows, const SphereVelocity* in,
                            VelocityCache& velocities) const {
  for (const std::uint32_t row : rows) {
    for (std::uint32_t i = 0; i < grid_.nx; ++i) {
      const std::uint32_t part = row_parts_[row * grid_.nx + i];
      const std::uint32_t count = part_start_[part + 1] - part_start_[part];
      std::copy(in, in + count, velocities.spheres.begin() + part_start_[part]);
      in += count;
    }
  }
}

void TileRanks::after_phase(std::size_t phase, VelocityCache& velocities) {
  if (!active_) return;
  shared_ = false;
  exchange_places(sends_[phase], receives_[phase], static_cast<int>(phase), velocities);
}

void TileRanks::exchange_places(std::vector<PlaceMessage>& sends,
                                std::vector<PlaceMessage>& receives, int tag,
                                VelocityCache& velocities) {
  std::vector<RankBytes> out;
  std::vector<RankBytes> in;
  out.reserve(sends.size());
  in.reserve(receives.size());
  for (PlaceMessage& m : sends) {
    for (std::size_t i = 0; i < m.places.size(); ++i) m.buffer[i] = velocities.spheres[m.places[i]];
    out.push_back({m.peer, bytes_of(m.buffer)});
  }
  for (PlaceMessage& m : receives) in.push_back({m.peer, bytes_of(m.buffer)});
  exchange_with_ranks(out, in, tag);
  for (const PlaceMessage& m : receives) {
    for (std::size_t i = 0; i < m.places.size(); ++i) velocities.spheres[m.places[i]] = m.buffer[i];
  }
}

void TileRanks::share_records(VelocityCache& velocities) {
  if (!active_ || shared_) return;
  const auto& rows = rank_rows_[static_cast<std::size_t>(rank_)];
  my_records_.resize(row_records(rows));
  pack_rows(rows, velocities, my_records_.data());
  gather_items(my_records_, all_records_, counts_, ranks_,
               [&](int r) { return row_records(rank_rows_[static_cast<std::size_t>(r)]); });
  const SphereVelocity* in = all_records_.data();
  for (int r = 0; r < ranks_; ++r) {
    const auto& theirs = rank_rows_[static_cast<std::size_t>(r)];
    if (r != rank_) unpack_rows(theirs, in, velocities);
    in += row_records(theirs);
  }
  shared_ = true;
}

std::size_t TileRanks::part_actions(const ColouredPass& pass, std::uint32_t part) {
  const std::size_t batched =
      pass.colouring.first_member(part + 1) - pass.colouring.first_member(part);
  const std::size_t sequential = pass.part_sequential[part + 1] - pass.part_sequential[part];
  return batched + sequential;
}

void TileRanks::share_solution(Contacts& contacts, const ColouredPass& pass,
                               VelocityCache& velocities) {
  share_records(velocities);
  share_actions(contacts, pass);
}

void TileRanks::share_pass(std::vector<PartSums>& part_sums) {
  if (!active_) return;
  actions_shared_ = false;
  share_parts(part_sums);
}

void TileRanks::share_bytes(std::span<std::byte> items, std::size_t size,
                            const std::vector<std::vector<std::uint32_t>>& rank_items) {
  if (!active_) return;
  const auto& mine = rank_items[static_cast<std::size_t>(rank_)];
  my_bytes_.resize(mine.size() * size);
  std::byte* out = my_bytes_.data();
  for (const std::uint32_t i : mine) out = std::copy_n(items.data() + i * size, size, out);
  gather_items(my_bytes_, all_bytes_, counts_, ranks_,
               [&](int r) { return rank_items[static_cast<std::size_t>(r)].size() * size; });
  const std::byte* in = all_bytes_.data();
  for (int r = 0; r < ranks_; ++r) {
    for (const std::uint32_t i : rank_items[static_cast<std::size_t>(r)]) {
      if (r != rank_) std::copy_n(in, size, items.data() + i * size);
      in += size;
    }
  }
}

void TileRanks::share_actions(Contacts& contacts, const ColouredPass& pass) {
  if (!active_ || actions_shared_) return;
  actions_shared_ = true;
  gather_actions(contacts, pass);
}

void TileRanks::gather_actions(Contacts& contacts, const ColouredPass& pass) {
  const std::size_t pairs = contacts.pairs.size();
  // a part's actions: its batched pairs (colour order), then its sequential group
  const auto for_each_action = [&](std::uint32_t p, auto&& visit) {
    for (std::uint32_t k = pass.colouring.first_member(p); k < pass.colouring.first_member(p + 1);
         ++k) {
      visit(contacts.pair_actions[k]);
    }
    for (std::uint32_t j = pass.part_sequential[p]; j < pass.part_sequential[p + 1]; ++j) {
      const ContactIndex k = pass.sequential[j];
      visit(k < pairs ? contacts.pair_actions[k] : contacts.wall_actions[k - pairs]);
    }
  };
  // a piston piece's actions: its contacts' (split_piston.hpp)
  const SplitPiston& split = pass.split_piston;
  const auto for_each_piston_action = [&](std::uint32_t p, auto&& visit) {
    for (std::uint32_t j = split.piece_start[p]; j < split.piece_start[p + 1]; ++j) {
      visit(contacts.wall_actions[split.walls[j]]);
    }
  };
  const auto actions_of = [&](int r) {
    std::size_t n = 0;
    for (const std::uint32_t p : rank_parts_[static_cast<std::size_t>(r)]) {
      n += part_actions(pass, p);
    }
    for (const std::uint32_t p : rank_piston_pieces_[static_cast<std::size_t>(r)]) {
      n += split.piece_start[p + 1] - split.piece_start[p];
    }
    return n;
  };
  my_actions_.clear();
  const auto keep = [&](const ContactAction& a) { my_actions_.push_back(a); };
  for (const std::uint32_t p : rank_parts_[static_cast<std::size_t>(rank_)]) {
    for_each_action(p, keep);
  }
  for (const std::uint32_t p : rank_piston_pieces_[static_cast<std::size_t>(rank_)]) {
    for_each_piston_action(p, keep);
  }
  gather_items(my_actions_, all_actions_, counts_, ranks_, actions_of);
  const ContactAction* action = all_actions_.data();
  const auto take = [&](ContactAction& a) { a = *action++; };
  for (int r = 0; r < ranks_; ++r) {
    if (r == rank_) {
      action += actions_of(r);
      continue;
    }
    for (const std::uint32_t p : rank_parts_[static_cast<std::size_t>(r)]) {
      for_each_action(p, take);
    }
    for (const std::uint32_t p : rank_piston_pieces_[static_cast<std::size_t>(r)]) {
      for_each_piston_action(p, take);
    }
  }
}

}  // namespace cdpowder
