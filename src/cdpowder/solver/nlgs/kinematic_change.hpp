// kinematic_change.hpp — how much the last pass changed the step's end velocities, against
// how fast the packing moves: the measures of the kinematic stopping rule
// (SolverSettings::kinematic_tolerance, physics.md §7.3).
#pragma once

#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/aligned_vector.hpp"
#include "cdpowder/core/index.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/core/vec3.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace cdpowder {

class TileRanks;  // tile_ranks.hpp

/// What one pass did to the end velocities. A sphere's surface velocity is measured as
/// u = √(|v|² + R²|ω|²), within √2 of the fastest point of its surface |v| + R|ω|.
struct PassMotion {
  double largest_change = 0.0;  ///< max over the spheres of u(Δv, Δω) [R/t0]
  /// √(mean over the spheres of u(Δv, Δω)²), when begin_step asked for it; else 0 [R/t0]
  double rms_change = 0.0;
  double rms_surface_speed = 0.0;  ///< √(mean over the spheres of u(v, ω)²) after the pass [R/t0]
  double piston_change = 0.0;      ///< |ΔV_P| [R/t0]
};

/// Compares the velocities after a pass with those it started from. The snapshot a pass
/// is measured against is taken in the same pass that measures the pass before it, so a
/// pass costs one pass over the spheres; only a change of the velocities between passes
/// (the mixing) needs a fresh copy. Buffers are kept from pass to pass and step to step
/// (no allocation in steady state).
class KinematicChange {
 public:
  /// Remembers v*, ω*, V_P* before the first pass of a step, and R² of every sphere from
  /// the cache's Δt/m and Δt/I (solid sphere: I = 0.4 m R²). The spheres are taken in pieces
  /// of consecutive records: piece p is records [piece_start[p], piece_start[p + 1]) (a tiled
  /// step's tiles, their records in tile order: tile_order.hpp); empty, one piece of all. The
  /// pieces are fixed by the tiling alone, and their sums are added piece by piece, so the bits
  /// do not depend on how many threads or ranks take them. With `ranks` active (tile_ranks.hpp)
  /// this rank measures its own tiles' pieces, and the pieces' measures go to every rank. With
  /// `rms_change` every after_pass of the step also sums the squared changes
  /// (PassMotion::rms_change; solver.kinematic_norm = "rms"). The pieces on the threads of
  /// `runner` when given, handed out in `piece_order` (ColouredPass::strip_order: each thread
  /// takes the rows of tiles it solves), or in piece order where it is empty.
  void begin_step(const VelocityCache& velocities, std::span<const std::uint32_t> piece_start = {},
                  bool rms_change = false, TileRanks* ranks = nullptr,
                  PieceRunner* runner = nullptr, std::span<const std::uint32_t> piece_order = {});

  /// Remembers the velocities again after something other than a pass changed them (the
  /// mixing), so the next pass is measured from them; the pieces on the threads of `runner`
  /// when given.
  void velocities_changed(const VelocityCache& velocities, PieceRunner* runner = nullptr);

  /// The change since the last snapshot, which then moves to the velocities now. The RMS
  /// speed is summed only when `with_speed` (the rule reads it once its window is full);
  /// otherwise it is 0. The pieces run on the threads of `runner` when given; their sums are
  /// added in piece order, so the bits do not depend on it.
  [[nodiscard]] PassMotion after_pass(const VelocityCache& velocities, bool with_speed,
                                      PieceRunner* runner = nullptr);

  /// Pieces the spheres are taken in (begin_step).
  [[nodiscard]] std::uint32_t pieces() const {
    return static_cast<std::uint32_t>(piece_blocks_.size() - 1);
  }

  /// One piece's largest squared change and sums of squared speeds and changes, on a cache line
  /// of its own (threads write them side by side; ranks send them as bytes).
  struct alignas(64) PieceMotion {
    double largest_sq = 0.0;
    double sum_sq = 0.0;
    double change_sum_sq = 0.0;
  };

  /// Spheres side by side: a block holds four, field by field (lane l = sphere 4b + l), so
  /// the pass runs 2 (SSE2) or 4 (AVX2) lanes at a time (lanes.hpp).
  static constexpr std::size_t kBlock = 4;

  /// Blocks that hold `spheres` spheres.
  static constexpr std::size_t blocks_of(std::size_t spheres) {
    return (spheres + kBlock - 1) / kBlock;
  }

  /// The snapshot of spheres 4b .. 4b + 3 (zeros past the last sphere).
  struct alignas(32) Block {
    std::array<std::array<double, kBlock>, 3> linear;
    std::array<std::array<double, kBlock>, 3> angular;
  };

 private:
  [[nodiscard]] PieceMotion measure_piece(const VelocityCache& velocities, std::uint32_t piece,
                                          bool with_speed);
  void copy_piece(const VelocityCache& velocities, std::uint32_t piece);

  /// Runs measure or copy for the pieces this rank takes: its own tiles' with `ranks_`
  /// active, else all.
  template <typename Task>
  void for_my_pieces(PieceRunner* runner, const Task& task);

  std::vector<Block> start_;
  /// R² per place in the blocks, each piece's last block filled with zeros
  AlignedVector<double> radius_sq_;
  /// piece p: records [piece_records_[p], piece_records_[p + 1]) in blocks
  /// [piece_blocks_[p], piece_blocks_[p + 1]) of the snapshot (its records from 4·first on)
  std::vector<std::size_t> piece_records_{0, 0};
  std::vector<std::size_t> piece_blocks_{0, 0};
  std::vector<std::uint32_t> piece_order_;  ///< begin_step's piece_order (empty: piece order)
  TileRanks* ranks_ = nullptr;              ///< begin_step's, when active
  std::vector<PieceMotion> measured_;       ///< scratch of after_pass
  double piston_start_ = 0.0;
  bool rms_change_ = false;  ///< begin_step's rms_change
};

}  // namespace cdpowder
