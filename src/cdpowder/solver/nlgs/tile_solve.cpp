// tile_solve.cpp — a tiled step's pass and mixing in pieces (tile_solve.hpp).
#include "cdpowder/solver/nlgs/tile_solve.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/solver/nlgs/mixed_actions.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

namespace cdpowder {

bool mix_tiled_step(AlignedVector<double>& start, AlignedVector<double>& swept, MixedModes modes,
                    AndersonAccelerator& accelerator, Contacts& contacts, VelocityCache& velocities,
                    ColouredPass& pass, TileThreads* threads, KinematicChange* kinematic,
                    std::vector<AndersonAccelerator::PassSums>& range_sums) {
  const std::size_t stride = modes.doubles_per_action();
  // the combined contact indices (pairs, then walls) of range r: part r's batched pairs for
  // r < parts (the pairs are stored in colour order during the solve), then the rest
  const PairColouring& colouring = pass.colouring;
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  const auto range = [&](std::uint32_t r) {
    return r < parts ? std::pair<std::size_t, std::size_t>{colouring.first_member(r),
                                                           colouring.first_member(r + 1)}
                     : std::pair<std::size_t, std::size_t>{colouring.first_member(parts),
                                                           contacts.size()};
  };
  swept.resize(stride * contacts.size());
  accelerator.begin(swept.size());
  range_sums.resize(parts + 1);
  run_pieces(threads, parts + 1, [&](std::uint32_t r) {
    const auto [first, last] = range(r);
    flatten_range(contacts, modes, first, last, swept);
    range_sums[r] = accelerator.pass(start.data(), swept.data(), first * stride, last * stride);
  });
  if (!accelerator.fit(std::span<const AndersonAccelerator::PassSums>(range_sums))) {
    return false;
  }

  // the mixed actions take the place of the start (read by the passes above alone)
  AlignedVector<double>& mixed = start;
  std::vector<ContactAction>& deltas = pass.deltas;
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
      const std::uint32_t first = pass.phase_parts[phase];
      run_pieces(threads, pass.phase_parts[phase + 1] - first,
                 [&](std::uint32_t i) { take_part(first + i); });
    }
  });
  if (kinematic != nullptr) kinematic->velocities_changed(velocities, threads);
  return true;
}

}  // namespace cdpowder
