// coloured_pass.cpp — batches of independent pair contacts, and of bottom-wall contacts,
// solved side by side (coloured_pass.hpp). The lane arithmetic is solve_pair's (solve_wall's
// for the walls), operation for operation (Eigen's 3-vector dot products sum left to right, its
// cross products are the textbook formula), with the kernel's two branches computed in every
// lane and selected: the same bits, contact by contact (coloured_kernel.inc). The kernel is
// compiled three times: for SSE2 (2 lanes per register, the x86-64 baseline without -march flags),
// for AVX2 (4 lanes) and for AVX-512 (8 lanes: two batches of a colour), chosen at run time. None
// uses fused multiply-add (-ffp-contract=off), so the results do not depend on the machine.
#include "cdpowder/solver/nlgs/coloured_pass.hpp"

#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/solver/nlgs/group_by_part.hpp"
#include "cdpowder/solver/nlgs/visit_contact.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <type_traits>

namespace cdpowder {

// The kernel for SSE2 (the x86-64 baseline, 2 lanes per register), AVX2 (4 lanes) and
// AVX-512 (8 lanes: two batches per call), chosen at run time: the same IEEE operations on the
// same operands, so the same bits.
#define CDP_LANE_CODE "cdpowder/solver/nlgs/coloured_kernel.inc"
#define CDP_LANE_CODE_AVX512
#include "cdpowder/core/lanes_instantiate.inc"

namespace {

/// Lane `lane` of `pair`: pair contact k (in colour order) of the step, whose record is
/// pass.pair_record(contacts, k).
void fill_lane(const Contacts& contacts, const ColouredPass& pass, const VelocityCache& velocities,
               ContactIndex k, std::size_t lane, BatchPair& pair) {
  const PairProblem& p = pass.pair_record(contacts, k);
  const SphereVelocity& a = velocities.spheres[p.a];
  const SphereVelocity& b = velocities.spheres[p.b];
  pair.x_row[lane] = k * kRecordDoubles;
  pair.a_row[lane] = p.a * kRecordDoubles;
  pair.b_row[lane] = p.b * kRecordDoubles;
  pair.nx[lane] = p.normal.x();
  pair.ny[lane] = p.normal.y();
  pair.nz[lane] = p.normal.z();
  pair.gap_rate[lane] = p.gap_rate;
  pair.lever_a[lane] = p.lever_a;
  pair.lever_b[lane] = p.lever_b;
  pair.inv_dt_w_n[lane] = p.inv_dt_w_n;
  pair.inv_dt_w_t[lane] = p.inv_dt_w_t;
  pair.inv_dt_w_r[lane] = p.inv_dt_w_r;
  pair.cohesion[lane] = p.cohesion;
  pair.mu[lane] = p.mu;
  pair.roll_cap[lane] = p.roll_cap;
  pair.twist_cap[lane] = p.twist_cap;
  const detail::ModeBlock block = pair_mode_block(p, a, b);
  pair.coupling[lane] = block.coupling;
  pair.inv_r_sq[lane] = block.inv_r_sq;
  pair.mass_a[lane] = a.dt_inverse_mass;
  pair.inertia_a[lane] = a.dt_inverse_inertia;
  pair.mass_b[lane] = b.dt_inverse_mass;
  pair.inertia_b[lane] = b.dt_inverse_inertia;
}

/// Lane `lane` of `pair`: wall contact w of the step (a bottom-wall contact), with solve_wall's
/// mode constants.
void fill_wall_lane(const Contacts& contacts, const VelocityCache& velocities, ContactIndex w,
                    std::size_t lane, WallBatchPair& pair) {
  const WallProblem& p = contacts.walls[w];
  const SphereVelocity& s = velocities.spheres[p.sphere];
  pair.x_row[lane] = w * kRecordDoubles;
  pair.s_row[lane] = p.sphere * kRecordDoubles;
  pair.nx[lane] = p.normal.x();
  pair.ny[lane] = p.normal.y();
  pair.nz[lane] = p.normal.z();
  pair.gap_rate[lane] = p.gap_rate;
  pair.radius[lane] = p.radius;
  pair.inv_dt_w_n[lane] = p.inv_dt_w_n;
  pair.inv_dt_w_t[lane] = p.inv_dt_w_t;
  pair.inv_dt_w_r[lane] = p.inv_dt_w_r;
  pair.cohesion[lane] = p.cohesion;
  pair.mu[lane] = p.mu;
  pair.roll_cap[lane] = p.roll_cap;
  pair.twist_cap[lane] = p.twist_cap;
  pair.coupling[lane] = -p.radius * s.dt_inverse_inertia;
  pair.inv_r_sq[lane] = detail::torque_scale_sq(p.radius);
  pair.mass[lane] = s.dt_inverse_mass;
  pair.inertia[lane] = s.dt_inverse_inertia;
}

/// Batches (BatchPair or WallBatchPair) in use for `count` contacts, with the padding batch.
std::size_t batches_for(std::size_t count) {
  const std::size_t batches = (count + kBatchLanes - 1) / kBatchLanes;
  return batches + batches % 2;
}

/// Fills batches next, next + 1, … of `pairs` with contacts member(begin) … member(end − 1),
/// fill(contact, lane, pair) writing one lane: unused lanes repeat a used lane of their
/// register pair (lane 0 where it has none), and a padding batch (no lane in use) repeats the
/// first batch of its pair when the batches are odd in number (BatchPair).
template <typename Pair, typename Member, typename Fill>
void fill_batches(std::uint32_t begin, std::uint32_t end, const Member& member, const Fill& fill,
                  std::vector<Pair>& pairs, std::size_t& next) {
  for (std::uint32_t m = begin; m < end; m += kBatchLanes) {
    Pair& pair = pairs[next / 2];
    const std::size_t half = next % 2;
    ++next;
    const std::uint32_t lanes = std::min<std::uint32_t>(kBatchLanes, end - m);
    pair.lanes[half] = lanes;
    for (std::uint32_t l = 0; l < kBatchLanes; ++l) {
      const std::uint32_t pair_first = l & ~std::uint32_t{1};
      const std::uint32_t lane = l < lanes ? l : (pair_first < lanes ? pair_first : 0);
      fill(member(m + lane), half * kBatchLanes + l, pair);
    }
  }
  if (next % 2 != 0) {  // padding: the first batch again, no lane in use
    Pair& pair = pairs[next / 2];
    ++next;
    pair.lanes[1] = 0;
    for (std::uint32_t l = 0; l < kBatchLanes; ++l) {
      fill(static_cast<ContactIndex>(pair.x_row[l] / kRecordDoubles), kBatchLanes + l, pair);
    }
  }
}

}  // namespace

namespace {

/// The values of part p's batches and wall batches filled again lane by lane, each lane from
/// the contact its row names (its colour-order index): what build_batches writes, when the
/// colouring and the rows are those of its last call.
void refill_part(const Contacts& contacts, const VelocityCache& velocities, std::size_t part,
                 ColouredPass& pass) {
  const PairColouring& colouring = pass.colouring;
  const std::uint32_t first = pass.colour_batches[colouring.first_colour(part)] / 2;
  const std::uint32_t last = pass.colour_batches[colouring.first_colour(part + 1)] / 2;
  for (std::uint32_t i = first; i < last; ++i) {
    BatchPair& pair = pass.batch_pairs[i];
    for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
      fill_lane(contacts, pass, velocities, pair.x_row[lane] / kRecordDoubles, lane, pair);
    }
  }
  for (std::uint32_t i = pass.part_wall_batches[part] / 2; i < pass.part_wall_batches[part + 1] / 2;
       ++i) {
    WallBatchPair& pair = pass.wall_batch_pairs[i];
    for (std::size_t lane = 0; lane < kPairLanes; ++lane) {
      fill_wall_lane(contacts, velocities, pair.x_row[lane] / kRecordDoubles, lane, pair);
    }
  }
}

}  // namespace

bool ColouringInputs::match(const std::vector<PairProblem>& pairs,
                            const std::vector<WallProblem>& walls,
                            std::span<const std::uint32_t> sphere_part, std::size_t chunk,
                            PieceRunner* runner) const {
  if (!recorded_ || chunk != chunk_ || pairs.size() != pairs_.size() ||
      walls.size() != walls_.size() ||
      !std::equal(sphere_part.begin(), sphere_part.end(), sphere_part_.begin(),
                  sphere_part_.end())) {
    return false;
  }
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    if (contact_key(walls[w]) != walls_[w]) return false;
  }
  // the pairs' records are 128 bytes each: a stream worth sharing; the answer is an AND
  std::atomic<bool> same{true};
  run_chunks(runner, pairs_.size(), [&](std::size_t first, std::size_t last) {
    if (!same.load(std::memory_order_relaxed)) return;  // another piece found one already
    for (std::size_t k = first; k < last; ++k) {
      if (contact_key(pairs[k]) != pairs_[k]) {
        same.store(false, std::memory_order_relaxed);
        return;
      }
    }
  });
  return same.load(std::memory_order_relaxed);
}

void ColouringInputs::record(const std::vector<PairProblem>& pairs,
                             const std::vector<WallProblem>& walls,
                             std::span<const std::uint32_t> sphere_part, std::size_t chunk) {
  pairs_.resize(pairs.size());
  for (std::size_t k = 0; k < pairs_.size(); ++k) pairs_[k] = contact_key(pairs[k]);
  walls_.resize(walls.size());
  for (std::size_t w = 0; w < walls_.size(); ++w) walls_[w] = contact_key(walls[w]);
  sphere_part_.assign(sphere_part.begin(), sphere_part.end());
  chunk_ = chunk;
  recorded_ = true;
}

namespace {

/// Each part's sequential group (its overflow pairs, then its wall contacts in storage order;
/// of these, the bottom-wall contacts before the first piston contact go into wall batches)
/// and its groups in storage order (its colours, then the sequential group). Returns the wall
/// batches the bottom-wall contacts need.
std::size_t build_sequential_groups(const Contacts& contacts, ColouredPass& pass) {
  const PairColouring& colouring = pass.colouring;
  const std::size_t colours = colouring.colours();
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  const std::size_t parts = colouring.parts();
  // the walls part by part, each part's in storage order
  const std::vector<ContactIndex>& walls = pass.wall_order;
  group_by_part(
      contacts.walls.size(), parts,
      [&](std::size_t w) -> std::size_t { return pass.wall_part.empty() ? 0 : pass.wall_part[w]; },
      pass.wall_start, pass.part_next, pass.wall_order);
  pass.sequential.clear();
  pass.group_order.clear();
  pass.part_sequential.resize(parts + 1);
  pass.bottom_walls.resize(parts);
  pass.part_groups.resize(parts + 1);
  pass.part_wall_batches.resize(parts + 1);
  std::size_t wall_batch_count = 0;
  const bool split = pass.split_piston.active();
  for (std::size_t p = 0; p < parts; ++p) {
    pass.part_sequential[p] = static_cast<std::uint32_t>(pass.sequential.size());
    pass.sequential.insert(pass.sequential.end(),
                           colouring.overflow.begin() + colouring.part_overflow[p],
                           colouring.overflow.begin() + colouring.part_overflow[p + 1]);
    const auto bottom_first = static_cast<std::uint32_t>(pass.sequential.size());
    std::uint32_t bottom_last = bottom_first;
    for (std::uint32_t j = pass.wall_start[p]; j < pass.wall_start[p + 1]; ++j) {
      const ContactIndex w = walls[j];
      // split piston contacts are solved tile by tile after the hub (split_piston.hpp)
      if (split && contacts.walls[w].wall == WallKind::Piston) continue;
      if (contacts.walls[w].wall == WallKind::Bottom &&
          bottom_last == static_cast<std::uint32_t>(pass.sequential.size())) {
        ++bottom_last;
      }
      pass.sequential.push_back(n_pairs + w);
    }
    pass.bottom_walls[p] = {bottom_first, bottom_last};
    // side by side only if no two share a sphere: detection lists them in sphere order, one
    // per sphere at most (debug builds check it)
    CDP_ASSERT(std::adjacent_find(pass.sequential.begin() + bottom_first,
                                  pass.sequential.begin() + bottom_last,
                                  [&](ContactIndex k, ContactIndex after) {
                                    return contacts.walls[k - n_pairs].sphere >=
                                           contacts.walls[after - n_pairs].sphere;
                                  }) == pass.sequential.begin() + bottom_last,
               "bottom-wall contacts in increasing sphere order");
    wall_batch_count += batches_for(bottom_last - bottom_first);
    // the part's colours in storage order, then its sequential group
    pass.part_groups[p] = static_cast<std::uint32_t>(pass.group_order.size());
    for (std::uint32_t c = colouring.first_colour(p); c < colouring.first_colour(p + 1); ++c) {
      pass.group_order.push_back(c);
    }
    pass.group_order.push_back(static_cast<std::uint32_t>(colours + p));
  }
  pass.part_sequential[parts] = static_cast<std::uint32_t>(pass.sequential.size());
  pass.part_groups[parts] = static_cast<std::uint32_t>(pass.group_order.size());
  return wall_batch_count;
}

}  // namespace

void build_batches(const Contacts& contacts, const VelocityCache& velocities, ColouredPass& pass) {
  pass.built_from.forget();
  const PairColouring& colouring = pass.colouring;
  const std::size_t colours = colouring.colours();
  // Every field of every lane is written below, so the vector keeps last step's pairs of
  // batches (clearing and value-initialising them again cost ≈ 40 instructions per pair on the
  // paper's fronts). Unused lanes and padding batches repeat used lanes (BatchPair); on SSE2 a
  // register pair of lanes with none in use is not solved, as a repeat there would follow the
  // first solve.
  std::size_t batch_count = 0;
  for (std::size_t c = 0; c < colours; ++c) {
    batch_count += batches_for(colouring.colour_start[c + 1] - colouring.colour_start[c]);
  }
  pass.batch_pairs.resize(batch_count / 2);
  // the records' offsets in BatchPair are 32-bit
  CDP_ASSERT(contacts.pairs.size() <= UINT32_MAX / kRecordDoubles &&
                 contacts.walls.size() <= UINT32_MAX / kRecordDoubles &&
                 velocities.spheres.size() <= UINT32_MAX / kRecordDoubles,
             "records addressable by 32-bit offsets");
  pass.colour_batches.assign(colours + 1, 0);
  std::size_t next = 0;
  const auto fill_pair = [&](ContactIndex k, std::size_t lane, BatchPair& pair) {
    fill_lane(contacts, pass, velocities, k, lane, pair);
  };
  for (std::size_t c = 0; c < colours; ++c) {
    fill_batches(
        colouring.colour_start[c], colouring.colour_start[c + 1],
        [&](std::uint32_t m) { return colouring.members[m]; }, fill_pair, pass.batch_pairs, next);
    pass.colour_batches[c + 1] = static_cast<std::uint32_t>(next);
  }
  CDP_ASSERT(next == batch_count, "every batch filled");
  const std::size_t wall_batch_count = build_sequential_groups(contacts, pass);
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  const std::size_t parts = colouring.parts();
  // the bottom-wall batches, part by part
  pass.wall_batch_pairs.resize(wall_batch_count / 2);
  const auto fill_wall = [&](ContactIndex w, std::size_t lane, WallBatchPair& pair) {
    fill_wall_lane(contacts, velocities, w, lane, pair);
  };
  std::size_t next_wall = 0;
  for (std::size_t p = 0; p < parts; ++p) {
    pass.part_wall_batches[p] = static_cast<std::uint32_t>(next_wall);
    fill_batches(
        pass.bottom_walls[p].first, pass.bottom_walls[p].second,
        [&](std::uint32_t j) { return pass.sequential[j] - n_pairs; }, fill_wall,
        pass.wall_batch_pairs, next_wall);
  }
  pass.part_wall_batches[parts] = static_cast<std::uint32_t>(next_wall);
  CDP_ASSERT(next_wall == wall_batch_count, "every wall batch filled");
}

namespace {

/// out[i] = v[from[i]] for i in [first, last) (`out` sized by the caller)
template <typename T>
void gather_range(const std::vector<T>& v, const std::vector<ContactIndex>& from, std::size_t first,
                  std::size_t last, std::vector<T>& out) {
  for (std::size_t i = first; i < last; ++i) out[i] = v[from[i]];
}

/// v[i] = old v[from[i]]
template <typename T>
void gather_into(std::vector<T>& v, const std::vector<ContactIndex>& from,
                 std::vector<T>& scratch) {
  scratch.resize(v.size());
  gather_range(v, from, 0, from.size(), scratch);
  v.swap(scratch);
}

/// v[from[i]] = old v[i]; each entry is written once, so in pieces on `pieces` when there is
/// one (run_chunks)
template <typename T>
void scatter_back(std::vector<T>& v, const std::vector<ContactIndex>& from, std::vector<T>& scratch,
                  PieceRunner* pieces) {
  scratch.resize(v.size());
  run_chunks(pieces, from.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) scratch[from[i]] = v[i];
  });
  v.swap(scratch);
}

}  // namespace

namespace {

/// The part of pair p (not tiled: 0).
std::uint32_t part_of(const PairProblem& p, const StepTiles* tiles) {
  return tiles == nullptr ? 0 : tiles->pair_part(p);
}

/// Each wall contact's part (tiles.hpp); empty when the step is not tiled.
void assign_wall_parts(const Contacts& contacts, const StepTiles* tiles,
                       std::vector<std::uint32_t>& wall_part) {
  wall_part.clear();
  if (tiles == nullptr) return;
  wall_part.resize(contacts.walls.size());
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    wall_part[k] = tiles->wall_part(contacts.walls[k]);
  }
}

}  // namespace

namespace {

/// A step whose colouring is kept (ColouringInputs): part by part (on the threads of `pieces`
/// when given), the part's actions into colour order (its members, and for the last part also
/// the overflow pairs, are a range of it), then its batches' values from the records. The
/// members are colour-order indices already (set by the build from these inputs).
void refill_kept_colouring(Contacts& contacts, const VelocityCache& velocities, ColouredPass& pass,
                           PieceRunner* pieces, std::span<const std::uint8_t> solved) {
  const PairColouring& colouring = pass.colouring;
  const std::vector<ContactIndex>& from = pass.storage_index;
  std::vector<ContactAction>& actions = pass.action_scratch;
  actions.resize(contacts.pair_actions.size());
  const auto parts = static_cast<std::uint32_t>(colouring.parts());
  // the parts handed out in strip order (ColouredPass::strip_order): the kept colouring's
  // parts are the step's, since its inputs include every sphere's part
  CDP_ASSERT(pass.strip_order.size() == parts, "a kept colouring of another tiling");
  run_pieces_in(pieces, pass.strip_order, parts, [&](std::uint32_t part) {
    const std::size_t first = colouring.first_member(part);
    const std::size_t last =
        part + 1 < parts ? colouring.first_member(part + 1) : contacts.pairs.size();
    gather_range(contacts.pair_actions, from, first, last, actions);
    if (solved.empty() || solved[part] != 0) refill_part(contacts, velocities, part, pass);
  });
  contacts.pair_actions.swap(actions);
}

}  // namespace

void prepare_coloured_pass(Contacts& contacts, const VelocityCache& velocities, ColouredPass& pass,
                           std::size_t chunk, const StepTiles* tiles, PieceRunner* pieces,
                           std::span<const std::uint8_t> solved) {
  if (tiles != nullptr && !tiles->tiled()) tiles = nullptr;
  const std::span<const std::uint32_t> sphere_part =
      tiles == nullptr ? std::span<const std::uint32_t>{} : std::span(tiles->sphere_part);
  pass.phase_parts = tiles == nullptr ? std::array<std::uint32_t, kTilePhases + 1>{0, 1, 1, 1, 1}
                                      : tiles->phase_parts;
  if (tiles == nullptr) {
    pass.strip_order.assign({0});
  } else {
    pass.strip_order.assign(tiles->part_of_tile.begin(), tiles->part_of_tile.end());
    for (std::uint32_t part = tiles->phase_parts[kTilePhases]; part < tiles->parts(); ++part) {
      pass.strip_order.push_back(part);
    }
  }
  // the actions are in colour order during the solve; the records and the cohesion flags stay
  // in storage order (ColouredPass::pair_record)
  if (pass.built_from.match(contacts.pairs, contacts.walls, sphere_part, chunk, pieces)) {
    refill_kept_colouring(contacts, velocities, pass, pieces, solved);
    pass.in_colour_order = true;
    return;
  }
  // whatever the record described is overwritten from here on
  pass.built_from.forget();
  // the pairs part by part, each part in storage order (a counting sort)
  const std::size_t parts = tiles == nullptr ? 1 : tiles->parts();
  std::vector<std::uint32_t>& pair_part = pass.pair_part;
  pair_part.resize(contacts.pairs.size());
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    pair_part[k] = part_of(contacts.pairs[k], tiles);
  }
  group_by_part(
      contacts.pairs.size(), parts, [&](std::size_t k) { return pair_part[k]; }, pass.part_start,
      pass.part_next, pass.part_order);
  PairColouring& colouring = pass.colouring;
  colour_parts(contacts.pairs, pass.part_order, pass.part_start, velocities.spheres.size(),
               kMaxColours, chunk, colouring, pass.masks);
  assign_wall_parts(contacts, tiles, pass.wall_part);
  group_by_part(
      contacts.walls.size(), parts,
      [&](std::size_t w) -> std::size_t {
        return tiles == nullptr ? 0 : tiles->sphere_part[contacts.walls[w].sphere];
      },
      pass.mixing_wall_start, pass.part_next, pass.mixing_walls);
  group_piston_contacts(contacts, tiles, pass.split_piston);
  // store the actions in the order the batches visit them, overflow last
  std::vector<ContactIndex>& from = pass.storage_index;
  from.assign(colouring.members.begin(), colouring.members.end());
  from.insert(from.end(), colouring.overflow.begin(), colouring.overflow.end());
  gather_into(contacts.pair_actions, from, pass.action_scratch);
  pass.in_colour_order = true;
  std::iota(colouring.members.begin(), colouring.members.end(), ContactIndex{0});
  std::iota(colouring.overflow.begin(), colouring.overflow.end(),
            static_cast<ContactIndex>(colouring.members.size()));
  build_batches(contacts, velocities, pass);
  pass.built_from.record(contacts.pairs, contacts.walls, sphere_part, chunk);
}

void restore_storage_order(Contacts& contacts, ColouredPass& pass, PieceRunner* pieces) {
  if (!pass.in_colour_order) return;  // not prepared
  const std::vector<ContactIndex>& from = pass.storage_index;
  CDP_ASSERT(from.size() == contacts.pairs.size() && from.size() == contacts.pair_actions.size(),
             "a storage index per pair");
  scatter_back(contacts.pair_actions, from, pass.action_scratch, pieces);
  pass.in_colour_order = false;  // storage_index is kept for the next step's prepare
}

void order_groups(ColouredPass& pass, VisitOrder policy, Rng& rng) {
  const PairColouring& colouring = pass.colouring;
  const std::vector<std::uint32_t>& chunk_colours = colouring.chunk_colours;
  const bool shuffle = policy != VisitOrder::Fixed;
  constexpr std::uint32_t kSequential = ~std::uint32_t{0};
  pass.group_order.clear();
  const std::size_t parts = colouring.parts();
  pass.part_groups.resize(parts + 1);
  for (std::size_t p = 0; p < parts; ++p) {
    // the part's chunks and its sequential group in a random order, and each chunk's colours
    // in a random order
    pass.chunk_order.clear();
    for (std::uint32_t j = colouring.part_chunks[p]; j < colouring.part_chunks[p + 1]; ++j) {
      pass.chunk_order.push_back(j);
    }
    pass.chunk_order.push_back(kSequential);
    if (shuffle) shuffle_indices(std::span<std::uint32_t>(pass.chunk_order), rng);
    pass.part_groups[p] = static_cast<std::uint32_t>(pass.group_order.size());
    for (const std::uint32_t chunk : pass.chunk_order) {
      if (chunk == kSequential) {
        pass.group_order.push_back(static_cast<std::uint32_t>(pass.colours() + p));
        continue;
      }
      const std::size_t first = pass.group_order.size();
      for (std::uint32_t c = chunk_colours[chunk]; c < chunk_colours[chunk + 1]; ++c) {
        pass.group_order.push_back(c);
      }
      if (shuffle) {
        shuffle_indices(std::span<std::uint32_t>(pass.group_order).subspan(first), rng);
      }
    }
  }
  pass.part_groups[parts] = static_cast<std::uint32_t>(pass.group_order.size());
  std::iota(pass.slot_order.begin(), pass.slot_order.end(), std::uint32_t{0});
  // one part (no tiles) draws nothing more: its order is that of a step before the tiles
  if (shuffle && parts > 1) shuffle_indices(std::span<std::uint32_t>(pass.slot_order), rng);
}

bool allow_kernel_isa(lanes::Isa widest) {
  return lanes::allow_isa(widest);
}

namespace {

using SolveBatches = void (*)(const BatchPair*, std::uint32_t, std::uint32_t, SphereVelocity*,
                              ContactAction*, PassSums&);
using ApplyBatches = void (*)(const BatchPair*, std::uint32_t, std::uint32_t, SphereVelocity*,
                              const ContactAction*);
using SolveWallBatches = void (*)(const WallBatchPair*, std::uint32_t, std::uint32_t,
                                  SphereVelocity*, ContactAction*, PassSums&);

/// The kernel for this CPU, with torques or without (ColouredPass::torques), for open
/// contacts rare or not (ColouredPass::open_rare): the same bits either way.
SolveBatches batch_kernel(bool torques, bool open_rare) {
  if (torques) {
    return open_rare ? CDP_WIDE_LANES_FOR_CPU(solve_batches<true, true>)
                     : CDP_WIDE_LANES_FOR_CPU(solve_batches<true, false>);
  }
  return open_rare ? CDP_WIDE_LANES_FOR_CPU(solve_batches<false, true>)
                   : CDP_WIDE_LANES_FOR_CPU(solve_batches<false, false>);
}

SolveWallBatches wall_kernel(bool open_rare) {
  return open_rare ? CDP_WIDE_LANES_FOR_CPU(solve_wall_batches<true>)
                   : CDP_WIDE_LANES_FOR_CPU(solve_wall_batches<false>);
}

/// Whether at most one visit in kOpenRare of a pass left its contact open (not closed): then
/// the next pass runs the kernel that skips the open branch where no lane of a call needs it.
/// The break-even lies between the compaction front (≈ 2.5 % of the visits open: the selects
/// are cheaper) and mid-run (≈ 0.25 %: the branch is cheaper);
/// docs/lab/2026-11-28-calls-without-an-open-lane.md.
constexpr std::size_t kOpenRare = 100;

bool open_contacts_rare(const PassSums& sums, std::size_t visits) {
  return (visits - std::min(sums.closed, visits)) * kOpenRare <= visits;
}

ApplyBatches apply_kernel(bool torques) {
  return torques ? CDP_WIDE_LANES_FOR_CPU(apply_batches<true>)
                 : CDP_WIDE_LANES_FOR_CPU(apply_batches<false>);
}

}  // namespace

void apply_part_deltas(const ColouredPass& pass, std::size_t part,
                       const std::vector<ContactAction>& deltas, VelocityCache& velocities) {
  // colour by colour: the AVX-512 kernel takes two batches at a time, which must not share a
  // sphere (two colours may)
  const ApplyBatches apply = apply_kernel(pass.torques);
  const PairColouring& colouring = pass.colouring;
  for (std::size_t c = colouring.first_colour(part); c < colouring.first_colour(part + 1); ++c) {
    apply(pass.batch_pairs.data(), pass.colour_batches[c], pass.colour_batches[c + 1],
          velocities.spheres.data(), deltas.data());
  }
}

void apply_overflow_deltas(const ColouredPass& pass, const std::vector<ContactAction>& deltas,
                           const Contacts& contacts, VelocityCache& velocities) {
  // the overflow pairs are stored part by part: part order is their order
  for (std::size_t p = 0; p < pass.parts(); ++p) {
    apply_part_overflow_deltas(pass, p, deltas, contacts, velocities);
  }
}

void apply_part_overflow_deltas(const ColouredPass& pass, std::size_t part,
                                const std::vector<ContactAction>& deltas, const Contacts& contacts,
                                VelocityCache& velocities) {
  const PairColouring& colouring = pass.colouring;
  for (std::uint32_t i = colouring.part_overflow[part]; i < colouring.part_overflow[part + 1];
       ++i) {
    const ContactIndex k = colouring.overflow[i];
    apply_pair_action(pass.pair_record(contacts, k), deltas[k], velocities);
  }
}

void apply_pair_deltas(const ColouredPass& pass, const std::vector<ContactAction>& deltas,
                       const Contacts& contacts, VelocityCache& velocities) {
  // colour by colour in storage order: each sphere gets its changes in the order of the
  // scalar loop over the pairs (no sphere twice in a colour), so the same bits
  for (std::size_t p = 0; p < pass.parts(); ++p) apply_part_deltas(pass, p, deltas, velocities);
  apply_overflow_deltas(pass, deltas, contacts, velocities);
}

PassSums run_coloured_part(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                           std::size_t part) {
  PassSums sums;
  const std::size_t colours = pass.colours();
  SphereVelocity* const spheres = velocities.spheres.data();
  ContactAction* const actions = contacts.pair_actions.data();
  const SolveBatches solve = batch_kernel(pass.torques, pass.open_rare);
  const SolveWallBatches solve_walls = wall_kernel(pass.open_rare);
  for (std::uint32_t i = pass.part_groups[part]; i < pass.part_groups[part + 1]; ++i) {
    const std::uint32_t group = pass.group_order[i];
    if (group >= colours) {
      // overflow pairs, bottom-wall batches, the other wall contacts: in the group's order
      const std::size_t p = group - colours;
      const auto [bottom_first, bottom_last] = pass.bottom_walls[p];
      for (std::uint32_t j = pass.part_sequential[p]; j < bottom_first; ++j) {
        visit_contact(pass.sequential[j], contacts, velocities, sums, pass.record_of());
      }
      if (bottom_first < bottom_last) {
        solve_walls(pass.wall_batch_pairs.data(), pass.part_wall_batches[p],
                    pass.part_wall_batches[p + 1], spheres, contacts.wall_actions.data(), sums);
      }
      for (std::uint32_t j = bottom_last; j < pass.part_sequential[p + 1]; ++j) {
        visit_contact(pass.sequential[j], contacts, velocities, sums, pass.record_of());
      }
      continue;
    }
    solve(pass.batch_pairs.data(), pass.colour_batches[group], pass.colour_batches[group + 1],
          spheres, actions, sums);
  }
  return sums;
}

PassSums run_coloured_pass(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                           TileThreads* threads, TileRanks* ranks) {
  const std::size_t parts = pass.parts();
  std::vector<PartSums>& part_sums = pass.part_sums;
  part_sums.resize(parts);
  PassSums split_sums;
  const bool shared = ranks != nullptr && ranks->active();
  for (const std::uint32_t slot : pass.slot_order) {
    if (slot == kTilePhases) {
      // the hub: its contacts touch spheres of any tile (every rank solves it, on the same
      // records of its spheres)
      if (shared) ranks->share_hub_records(velocities);
      for (std::size_t p = pass.phase_parts[kTilePhases]; p < parts; ++p) {
        part_sums[p].sums = run_coloured_part(contacts, velocities, pass, p);
      }
      if (pass.split_piston.active()) {
        split_sums = run_split_piston(contacts, velocities, pass.split_piston, threads, ranks);
      }
      continue;
    }
    if (shared) {
      // this rank's tiles of the phase, then the rows they wrote to the ranks that hold them
      const std::span<const std::uint32_t> mine = ranks->phase_parts(slot);
      run_pieces(threads, static_cast<std::uint32_t>(mine.size()), [&](std::uint32_t i) {
        part_sums[mine[i]].sums = run_coloured_part(contacts, velocities, pass, mine[i]);
      });
      ranks->after_phase(slot, velocities);
      continue;
    }
    const std::uint32_t first = pass.phase_parts[slot];
    run_pieces(threads, pass.phase_parts[slot + 1] - first, [&](std::uint32_t i) {
      part_sums[first + i].sums = run_coloured_part(contacts, velocities, pass, first + i);
    });
  }
  if (shared) ranks->share_pass(part_sums);
  PassSums sums;
  for (const PartSums& part : part_sums) sums.add_part(part.sums);
  sums.add_part(split_sums);
  pass.open_rare = open_contacts_rare(sums, contacts.size());
  return sums;
}

}  // namespace cdpowder
