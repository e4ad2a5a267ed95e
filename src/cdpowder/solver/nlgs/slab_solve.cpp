// slab_solve.cpp — a cut step's pass and mixing in pieces (slab_solve.hpp).
#include "cdpowder/solver/nlgs/slab_solve.hpp"

#include "cdpowder/contact/velocity_change.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

namespace cdpowder {

namespace {

/// A piece's result on a cache line of its own (the two threads write them side by side).
template <typename T>
struct alignas(64) OnItsLine {
  T value{};
};

/// The combined contact indices (pairs, then walls) of the mixing's three ranges: slab 0's
/// pairs, slab 1's pairs, and the rest (the pairs across the cut, the overflow pairs, walls).
std::array<std::pair<std::size_t, std::size_t>, 3> contact_ranges(const Contacts& contacts,
                                                                  const ColouredPass& pass) {
  // the pairs are stored in colour order during the solve, so a part's members are its pairs
  const PairColouring& colouring = pass.colouring;
  return {{{colouring.first_member(0), colouring.first_member(1)},
           {colouring.first_member(1), colouring.first_member(2)},
           {colouring.first_member(2), contacts.size()}}};
}

}  // namespace

PassSums cut_step_pass(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                       SlabThreads* threads, KinematicChange* kinematic, bool with_speed,
                       PassMotion& motion) {
  std::array<OnItsLine<KinematicChange::PieceMotion>, 2> measured{};
  const PassSums sums =
      run_coloured_pass(contacts, velocities, pass, threads, [&](std::uint32_t part) {
        if (kinematic != nullptr) {
          measured[part].value = kinematic->measure_piece(velocities, part, with_speed);
        }
      });
  if (kinematic != nullptr) {
    const std::array<KinematicChange::PieceMotion, 2> pieces{measured[0].value, measured[1].value};
    motion = kinematic->combine(velocities, std::span(pieces));
  }
  return sums;
}

bool mix_cut_step(const AlignedVector<double>& start, AlignedVector<double>& swept,
                  AlignedVector<double>& mixed, MixedModes modes, AndersonAccelerator& accelerator,
                  Contacts& contacts, VelocityCache& velocities, ColouredPass& pass,
                  SlabThreads* threads, KinematicChange* kinematic) {
  const std::size_t stride = modes.doubles_per_action();
  const auto ranges = contact_ranges(contacts, pass);
  swept.resize(stride * contacts.size());
  accelerator.begin(swept.size());
  // two pieces: slab 1's pairs, and slab 0's with the rest (the caller's, which it touches
  // next); the sums of the three ranges are kept apart and added in range order
  std::array<OnItsLine<AndersonAccelerator::PassSums>, 3> passed{};
  const auto pass_range = [&](std::size_t range) {
    const auto [first, last] = ranges[range];
    flatten_range(contacts, modes, first, last, swept);
    passed[range].value =
        accelerator.pass(start.data(), swept.data(), first * stride, last * stride);
  };
  run_pieces(threads, 2, [&](std::uint32_t piece) {
    pass_range(piece);
    if (piece == 0) pass_range(2);
  });
  const std::array<AndersonAccelerator::PassSums, 3> sums{passed[0].value, passed[1].value,
                                                          passed[2].value};
  if (!accelerator.fit(std::span(sums))) return false;

  mixed.resize(swept.size());
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
    // the rest first, on the caller: it touches spheres of both slabs
    const auto [rest, end] = ranges[2];
    take_pairs(rest, end);
    apply_part_deltas(pass, 2, deltas, velocities);
    apply_overflow_deltas(pass, deltas, contacts, velocities);
    for (std::size_t k = std::max(rest, pairs); k < end; ++k) {
      const std::size_t w = k - pairs;
      apply_wall_action(
          contacts.walls[w],
          take_mixed<kRolling, kTwisting>(mixed.data() + k * kStride, contacts.wall_actions[w]),
          velocities);
    }
    // then each slab's pairs, and the kinematic rule's snapshot of its spheres
    run_pieces(threads, 2, [&](std::uint32_t part) {
      take_pairs(ranges[part].first, ranges[part].second);
      apply_part_deltas(pass, part, deltas, velocities);
      if (kinematic != nullptr) kinematic->copy_piece(velocities, part);
    });
  });
  if (kinematic != nullptr) kinematic->copied(velocities);
  return true;
}

}  // namespace cdpowder
