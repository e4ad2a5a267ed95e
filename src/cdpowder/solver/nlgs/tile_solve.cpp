// tile_solve.cpp — a tiled step's pass and mixing in pieces (tile_solve.hpp).
#include "cdpowder/solver/nlgs/tile_solve.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/solver/nlgs/mixed_actions.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

namespace cdpowder {

namespace {

/// The combined contact indices (pairs, then walls) of range r: part r's batched pairs for
/// r < parts (the actions are stored in colour order during the solve), then the rest.
std::pair<std::size_t, std::size_t> range_of(const ColouredPass& pass, const Contacts& contacts,
                                             std::uint32_t r) {
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  const PairColouring& colouring = pass.colouring;
  return r < parts
             ? std::pair<std::size_t, std::size_t>{colouring.first_member(r),
                                                   colouring.first_member(r + 1)}
             : std::pair<std::size_t, std::size_t>{colouring.first_member(parts), contacts.size()};
}

/// The accelerator's first stage over every range: `swept` ← the actions, `range_sums` ← each
/// range's sums. An MPI job's ranks (`ranks` active) each take their own tiles' ranges, and
/// the hub's and the rest on every rank (their actions are every rank's:
/// TileRanks::share_sequential_actions); the tiles' sums then go to every rank.
void pass_over_ranges(const AlignedVector<double>& start, AlignedVector<double>& swept,
                      MixedModes modes, AndersonAccelerator& accelerator, const Contacts& contacts,
                      const ColouredPass& pass, TileThreads* threads,
                      std::vector<AndersonAccelerator::PassSums>& range_sums, TileRanks* ranks) {
  const std::size_t stride = modes.doubles_per_action();
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  swept.resize(stride * contacts.size());
  accelerator.begin(swept.size());
  range_sums.resize(parts + 1);
  const auto pass_range = [&](std::uint32_t r) {
    const auto [first, last] = range_of(pass, contacts, r);
    flatten_range(contacts, modes, first, last, swept);
    range_sums[r] = accelerator.pass(start.data(), swept.data(), first * stride, last * stride);
  };
  if (ranks == nullptr || !ranks->active()) {
    // the tiles handed out in strip order (ColouredPass::strip_order), then the rest
    run_pieces_in(threads, pass.strip_order, parts + 1, pass_range);
    return;
  }
  const std::span<const std::uint32_t> mine = ranks->own_parts();
  run_pieces(threads, static_cast<std::uint32_t>(mine.size()),
             [&](std::uint32_t i) { pass_range(mine[i]); });
  for (std::uint32_t r = pass.phase_parts[kTilePhases]; r <= parts; ++r) pass_range(r);
  ranks->share_parts(range_sums);
}

}  // namespace

bool mix_tiled_step(AlignedVector<double>& start, AlignedVector<double>& swept, MixedModes modes,
                    AndersonAccelerator& accelerator, Contacts& contacts, VelocityCache& velocities,
                    ColouredPass& pass, TileThreads* threads, KinematicChange* kinematic,
                    std::vector<AndersonAccelerator::PassSums>& range_sums, TileRanks* ranks) {
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  const auto range = [&](std::uint32_t r) { return range_of(pass, contacts, r); };
  pass_over_ranges(start, swept, modes, accelerator, contacts, pass, threads, range_sums, ranks);
  const bool shared = ranks != nullptr && ranks->active();
  if (!accelerator.fit(std::span<const AndersonAccelerator::PassSums>(range_sums))) {
    return false;
  }

  // the mixed actions take the place of the start (read by the passes above alone)
  AlignedVector<double>& mixed = start;
  std::vector<ContactAction>& deltas = pass.action_scratch;  // free during the solve
  deltas.resize(contacts.pairs.size());
  const std::size_t pairs = contacts.pairs.size();
  with_modes(modes, [&](auto rolling, auto twisting) {
    constexpr bool kRolling = decltype(rolling)::value;
    constexpr bool kTwisting = decltype(twisting)::value;
    constexpr std::size_t kStride = MixedModes{kRolling, kTwisting}.doubles_per_action();
    // the mixed actions of contacts [first, last), their pair changes into `deltas` (through
    // pointers held in locals: the vectors' own pointers would be reloaded after every store)
    const auto take_pairs = [&](std::size_t first, std::size_t last) {
      accelerator.mix(swept.data(), mixed.data(), first * kStride, last * kStride);
      const double* const mixed_values = mixed.data();
      ContactAction* const actions = contacts.pair_actions.data();
      ContactAction* const changes = deltas.data();
      for (std::size_t k = first; k < std::min(last, pairs); ++k) {
        changes[k] = take_mixed<kRolling, kTwisting>(mixed_values + k * kStride, actions[k]);
      }
    };
    // the rest first, on the caller: it touches spheres of any tile
    const auto [rest, end] = range(parts);
    take_pairs(rest, end);
    apply_overflow_deltas(pass, deltas, contacts, velocities);
    for (std::size_t k = std::max(rest, pairs); k < end; ++k) {
      const std::size_t w = k - pairs;
      apply_wall_action(
          contacts.walls[w],
          take_mixed<kRolling, kTwisting>(mixed.data() + k * kStride, contacts.wall_actions[w]),
          velocities);
    }
    // the hub's pairs, on the caller, then each phase's tiles side by side
    const auto take_part = [&](std::uint32_t part) {
      const auto [first, last] = range(part);
      take_pairs(first, last);
      apply_part_deltas(pass, part, deltas, velocities);
    };
    for (std::uint32_t part = pass.phase_parts[kTilePhases]; part < parts; ++part) {
      take_part(part);
    }
    for (std::size_t phase = 0; phase < kTilePhases; ++phase) {
      if (shared) {
        // this rank's tiles of the phase, then the rows they moved to the ranks that hold them
        const std::span<const std::uint32_t> mine = ranks->phase_parts(phase);
        run_pieces(threads, static_cast<std::uint32_t>(mine.size()),
                   [&](std::uint32_t i) { take_part(mine[i]); });
        ranks->after_phase(phase, velocities);
        continue;
      }
      const std::uint32_t first = pass.phase_parts[phase];
      run_pieces(threads, pass.phase_parts[phase + 1] - first,
                 [&](std::uint32_t i) { take_part(first + i); });
    }
  });
  if (kinematic != nullptr) kinematic->velocities_changed(velocities, threads);
  return true;
}

}  // namespace cdpowder
