// tile_solve.cpp — a tiled step's mixing in pieces, one a part (tile_solve.hpp).
#include "cdpowder/solver/nlgs/tile_solve.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/solver/nlgs/mixed_actions.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace cdpowder {

namespace {

/// Entries [first, last) of the flattened actions, in contacts (times the stride: doubles).
struct Segment {
  std::size_t first = 0;
  std::size_t last = 0;
};

/// Part p's three segments of the flattened actions (the pairs in colour order during the
/// solve, the walls in ColouredPass::mixing_walls): its batched pairs, its overflow pairs and
/// its walls (its spheres' bottom-wall and piston contacts; the hub's parts have none).
std::array<Segment, 3> segments_of(const ColouredPass& pass, const Contacts& contacts,
                                   std::uint32_t part) {
  const PairColouring& colouring = pass.colouring;
  const std::size_t overflow = colouring.first_member(pass.parts());
  const std::size_t pairs = contacts.pairs.size();
  return {Segment{colouring.first_member(part), colouring.first_member(part + 1)},
          Segment{overflow + colouring.part_overflow[part],
                  overflow + colouring.part_overflow[part + 1]},
          Segment{pairs + pass.mixing_wall_start[part], pairs + pass.mixing_wall_start[part + 1]}};
}

/// The accelerator's first stage over every part: the actions, as the pass left them, into the
/// accelerator's output() and `range_sums[p]` ← the sums of part p's segments against the
/// iterate `x`, added segment by segment. An MPI job's ranks (`ranks` active) each take their
/// own tiles' parts and every rank the hub's (whose actions every rank has); the tiles' sums
/// then go to every rank.
void pass_over_parts(const double* x, std::size_t n, MixedModes modes,
                     AndersonAccelerator& accelerator, const Contacts& contacts,
                     const ColouredPass& pass, TileThreads* threads,
                     std::vector<AndersonAccelerator::PassSums>& range_sums, TileRanks* ranks) {
  const std::size_t stride = modes.doubles_per_action();
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  accelerator.begin(n);
  double* const output = accelerator.output();
  range_sums.resize(parts);
  const ContactIndex* const wall_at = pass.mixing_walls.data();
  const auto pass_part = [&](std::uint32_t part) {
    AndersonAccelerator::PassSums& sums = range_sums[part];
    sums = {};
    for (const Segment& s : segments_of(pass, contacts, part)) {
      flatten_range(contacts, modes, s.first, s.last, output, wall_at);
      sums.add(accelerator.pass(x, s.first * stride, s.last * stride));
    }
  };
  if (ranks == nullptr || !ranks->active()) {
    // the tiles handed out in strip order (ColouredPass::strip_order), then the hub
    run_pieces_in(threads, pass.strip_order, parts, pass_part);
    return;
  }
  const std::span<const std::uint32_t> mine = ranks->own_parts();
  run_pieces(threads, static_cast<std::uint32_t>(mine.size()),
             [&](std::uint32_t i) { pass_part(mine[i]); });
  for (std::uint32_t part = pass.phase_parts[kTilePhases]; part < parts; ++part) pass_part(part);
  ranks->share_parts(range_sums);
}

}  // namespace

bool mix_tiled_step(const double* x, AlignedVector<double>& mixed, MixedModes modes,
                    AndersonAccelerator& accelerator, Contacts& contacts, VelocityCache& velocities,
                    ColouredPass& pass, TileThreads* threads, KinematicChange* kinematic,
                    std::vector<AndersonAccelerator::PassSums>& range_sums, TileRanks* ranks) {
  const auto parts = static_cast<std::uint32_t>(pass.parts());
  const std::size_t n = modes.doubles_per_action() * contacts.size();
  pass_over_parts(x, n, modes, accelerator, contacts, pass, threads, range_sums, ranks);
  const bool shared = ranks != nullptr && ranks->active();
  if (!accelerator.fit(std::span<const AndersonAccelerator::PassSums>(range_sums))) {
    return false;
  }

  // the mixed actions may take the place of x (read by the passes above alone)
  CDP_ASSERT(mixed.size() == n, "the mixed iterate holds every contact's carried fields");
  std::vector<ContactAction>& deltas = pass.action_scratch;  // free during the solve
  deltas.resize(contacts.pairs.size());
  std::vector<double>& piston_change = pass.part_piston_change;
  piston_change.assign(parts, 0.0);
  const std::size_t pairs = contacts.pairs.size();
  with_modes(modes, [&](auto rolling, auto twisting) {
    constexpr bool kRolling = decltype(rolling)::value;
    constexpr bool kTwisting = decltype(twisting)::value;
    constexpr std::size_t kStride = MixedModes{kRolling, kTwisting}.doubles_per_action();
    // part p's mixed actions: its pairs' changes into `deltas` and applied (the batched pairs
    // batch by batch, then the overflow pairs), then its walls' applied to their spheres, the
    // piston's share kept apart (the parts of a phase run side by side). Through pointers held
    // in locals: the vectors' own pointers would be reloaded after every store.
    const auto take_part = [&](std::uint32_t part) {
      const std::array<Segment, 3> segments = segments_of(pass, contacts, part);
      const double* const mixed_values = mixed.data();
      ContactAction* const actions = contacts.pair_actions.data();
      ContactAction* const changes = deltas.data();
      for (const Segment& s : {segments[0], segments[1]}) {
        accelerator.mix(mixed.data(), s.first * kStride, s.last * kStride);
        for (std::size_t k = s.first; k < s.last; ++k) {
          changes[k] = take_mixed<kRolling, kTwisting>(mixed_values + k * kStride, actions[k]);
        }
      }
      apply_part_deltas(pass, part, deltas, velocities);
      apply_part_overflow_deltas(pass, part, deltas, contacts, velocities);
      const Segment& walls = segments[2];
      accelerator.mix(mixed.data(), walls.first * kStride, walls.last * kStride);
      const ContactIndex* const wall_of = pass.mixing_walls.data();
      double piston = 0.0;
      for (std::size_t k = walls.first; k < walls.last; ++k) {
        const ContactIndex w = wall_of[k - pairs];
        const WallProblem& wall = contacts.walls[w];
        apply_wall_action(
            wall,
            take_mixed<kRolling, kTwisting>(mixed_values + k * kStride, contacts.wall_actions[w]),
            velocities.spheres[wall.sphere], piston);
      }
      piston_change[part] = piston;
    };
    // the hub's parts on the caller, then each phase's tiles side by side
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
  // the piston moves by its parts' changes, added in part order on every rank
  if (shared) ranks->share_parts(piston_change);
  for (const double change : piston_change) velocities.piston_velocity += change;
  if (kinematic != nullptr) kinematic->velocities_changed(velocities, threads);
  return true;
}

}  // namespace cdpowder
