// kinematic_change.cpp — one pass over the spheres after a pass, in lanes
// (kinematic_lanes.inc, compiled for SSE2 and for AVX2 like the coloured kernel).
#include "cdpowder/solver/nlgs/kinematic_change.hpp"

#include "cdpowder/core/lanes.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace cdpowder {

#define CDP_LANE_CODE "cdpowder/solver/nlgs/kinematic_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

void KinematicChange::begin_step(const VelocityCache& velocities, bool in_pieces, bool rms_change) {
  rms_change_ = rms_change;
  const std::vector<SphereVelocity>& spheres = velocities.spheres;
  const std::size_t n = spheres.size();
  const std::size_t blocks = blocks_of(n);
  // pieces of kPieceBlocks blocks (the last one shorter), or one piece
  const std::size_t pieces =
      in_pieces ? std::max<std::size_t>(1, (blocks + kPieceBlocks - 1) / kPieceBlocks) : 1;
  piece_blocks_.resize(pieces + 1);
  for (std::size_t p = 0; p < pieces; ++p) piece_blocks_[p] = p * kPieceBlocks;
  piece_blocks_[pieces] = blocks;
  radius_sq_.assign(blocks * kBlock, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    // I/m = (Δt/m)/(Δt/I) = 0.4 R²; a fixed sphere (Δt/I = 0) does not turn
    const SphereVelocity& s = spheres[i];
    radius_sq_[i] =
        s.dt_inverse_inertia > 0.0 ? 2.5 * s.dt_inverse_mass / s.dt_inverse_inertia : 0.0;
  }
  velocities_changed(velocities);
}

void KinematicChange::copy_piece(const VelocityCache& velocities, std::uint32_t piece) {
  const auto [first, last] = blocks_of_piece(piece);  // start_ sized by velocities_changed
  CDP_LANES_FOR_CPU(copy_into)
  (velocities.spheres.data(), velocities.spheres.size(), first, last, start_.data());
}

void KinematicChange::velocities_changed(const VelocityCache& velocities, PieceRunner* runner) {
  start_.resize(radius_sq_.size() / kBlock);
  run_pieces(runner, pieces(), [&](std::uint32_t piece) { copy_piece(velocities, piece); });
  piston_start_ = velocities.piston_velocity;
}

KinematicChange::PieceMotion KinematicChange::measure_piece(const VelocityCache& velocities,
                                                            std::uint32_t piece, bool with_speed) {
  const auto measure = with_speed ? (rms_change_ ? CDP_LANES_FOR_CPU(measure<true, true>)
                                                 : CDP_LANES_FOR_CPU(measure<true, false>))
                                  : (rms_change_ ? CDP_LANES_FOR_CPU(measure<false, true>)
                                                 : CDP_LANES_FOR_CPU(measure<false, false>));
  const auto [first, last] = blocks_of_piece(piece);
  PieceMotion out;
  measure(velocities.spheres.data(), velocities.spheres.size(), first, last, start_.data(),
          radius_sq_.data(), out.largest_sq, out.sum_sq, out.change_sum_sq);
  return out;
}

PassMotion KinematicChange::after_pass(const VelocityCache& velocities, bool with_speed,
                                       PieceRunner* runner) {
  measured_.resize(pieces());
  run_pieces(runner, pieces(), [&](std::uint32_t piece) {
    measured_[piece] = measure_piece(velocities, piece, with_speed);
  });
  // the pieces' sums in piece order: the same bits on any number of threads
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
