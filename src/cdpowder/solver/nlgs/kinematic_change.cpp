// kinematic_change.cpp — one pass over the spheres after a pass, in lanes
// (kinematic_lanes.inc, compiled for SSE2 and for AVX2 like the coloured kernel).
#include "cdpowder/solver/nlgs/kinematic_change.hpp"

#include "cdpowder/core/lanes.hpp"
#include "cdpowder/solver/nlgs/tile_ranks.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace cdpowder {

#define CDP_LANE_CODE "cdpowder/solver/nlgs/kinematic_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

void KinematicChange::begin_step(const VelocityCache& velocities,
                                 std::span<const std::uint32_t> piece_start, bool rms_change,
                                 TileRanks* ranks, PieceRunner* runner,
                                 std::span<const std::uint32_t> piece_order) {
  rms_change_ = rms_change;
  ranks_ = ranks != nullptr && ranks->active() ? ranks : nullptr;
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  const std::size_t n = spheres.size();
  // the pieces' records, and their blocks: each piece starts a block of its own
  if (piece_start.empty()) {
    piece_records_.assign({0, n});
  } else {
    piece_records_.assign(piece_start.begin(), piece_start.end());
  }
  const std::size_t pieces = piece_records_.size() - 1;
  piece_blocks_.resize(pieces + 1);
  piece_blocks_[0] = 0;
  for (std::size_t p = 0; p < pieces; ++p) {
    piece_blocks_[p + 1] = piece_blocks_[p] + blocks_of(piece_records_[p + 1] - piece_records_[p]);
  }
  radius_sq_.assign(piece_blocks_[pieces] * kBlock, 0.0);
  if (piece_order.size() == pieces) {
    piece_order_.assign(piece_order.begin(), piece_order.end());
  } else {
    piece_order_.clear();
  }
  run_pieces_in(runner, piece_order_, static_cast<std::uint32_t>(pieces), [&](std::uint32_t p) {
    double* const r_sq = radius_sq_.data() + kBlock * piece_blocks_[p];
    for (std::size_t i = piece_records_[p]; i < piece_records_[p + 1]; ++i) {
      // I/m = (Δt/m)/(Δt/I) = 0.4 R²; a fixed sphere (Δt/I = 0) does not turn
      const SphereVelocity& s = spheres[i];
      r_sq[i - piece_records_[p]] =
          s.dt_inverse_inertia > 0.0 ? 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia : 0.0;
    }
  });
  velocities_changed(velocities, runner);
}

template <typename Task>
void KinematicChange::for_my_pieces(PieceRunner* runner, const Task& task) {
  if (ranks_ == nullptr) {
    run_pieces_in(runner, piece_order_, pieces(), task);
    return;
  }
  const std::span<const std::uint32_t> mine = ranks_->own_parts();
  run_pieces(runner, static_cast<std::uint32_t>(mine.size()),
             [&](std::uint32_t i) { task(mine[i]); });
}

void KinematicChange::copy_piece(const VelocityCache& velocities, std::uint32_t piece) {
  const std::size_t first = piece_records_[piece];
  const std::size_t blocks = piece_blocks_[piece + 1] - piece_blocks_[piece];
  CDP_LANES_FOR_CPU(copy_into)
  (velocities.spheres.data() + first, piece_records_[piece + 1] - first, 0, blocks,
   start_.data() + piece_blocks_[piece]);
}

void KinematicChange::velocities_changed(const VelocityCache& velocities, PieceRunner* runner) {
  start_.resize(piece_blocks_.back());
  for_my_pieces(runner, [&](std::uint32_t piece) { copy_piece(velocities, piece); });
  piston_start_ = velocities.piston_velocity;
}

KinematicChange::PieceMotion KinematicChange::measure_piece(const VelocityCache& velocities,
                                                            std::uint32_t piece, bool with_speed) {
  const auto measure = with_speed ? (rms_change_ ? CDP_LANES_FOR_CPU(measure<true, true>)
                                                 : CDP_LANES_FOR_CPU(measure<true, false>))
                                  : (rms_change_ ? CDP_LANES_FOR_CPU(measure<false, true>)
                                                 : CDP_LANES_FOR_CPU(measure<false, false>));
  const std::size_t first = piece_records_[piece];
  const std::size_t first_block = piece_blocks_[piece];
  PieceMotion out;
  measure(velocities.spheres.data() + first, piece_records_[piece + 1] - first, 0,
          piece_blocks_[piece + 1] - first_block, start_.data() + first_block,
          radius_sq_.data() + kBlock * first_block, out.largest_sq, out.sum_sq, out.change_sum_sq);
  return out;
}

PassMotion KinematicChange::after_pass(const VelocityCache& velocities, bool with_speed,
                                       PieceRunner* runner) {
  measured_.resize(pieces());
  for_my_pieces(runner, [&](std::uint32_t piece) {
    measured_[piece] = measure_piece(velocities, piece, with_speed);
  });
  // the other ranks' pieces from them
  if (ranks_ != nullptr) ranks_->share_parts(measured_);
  // the pieces' sums in piece order: the same bits on any number of threads and ranks
  double largest_sq = measured_.front().largest_sq;
  double sum_sq = measured_.front().sum_sq;
  double change_sum_sq = measured_.front().change_sum_sq;
  for (std::size_t p = 1; p < measured_.size(); ++p) {
    largest_sq = std::max(largest_sq, measured_[p].largest_sq);
    sum_sq += measured_[p].sum_sq;
    change_sum_sq += measured_[p].change_sum_sq;
  }
  const std::size_t n = velocities.spheres.size();
  PassMotion motion;
  motion.largest_change = std::sqrt(largest_sq);
  motion.rms_surface_speed = n == 0 ? 0.0 : std::sqrt(sum_sq / static_cast<double>(n));
  motion.rms_change = n == 0 ? 0.0 : std::sqrt(change_sum_sq / static_cast<double>(n));
  motion.piston_change = std::abs(velocities.piston_velocity - piston_start_);
  piston_start_ = velocities.piston_velocity;
  return motion;
}

}  // namespace cdpowder
