// tile_ranks.hpp — a tiled step's passes shared among the ranks of an MPI job
// (core/ranks.hpp; docs/architecture.md, "Ranks (MPI)").
//
// Every rank holds the whole state and does the whole step, except the tiles of the colour
// phases: rank r solves the tiles of a strip of whole tile rows [j0, j1), the same tiles in
// every phase. A tile's contacts write the spheres of its own row and of the next, so after a
// phase the rows a rank wrote go to the ranks that hold them (the row's owner and the owner of
// the row below, for which it is the ghost row): one message per pair of neighbours. Before
// the hub (its contacts touch any tile) and at the end of a pass, every rank's own rows and
// its tiles' contact actions and sums go to every rank, so the hub, the kinematic rule, the
// mixing and everything after the solve run on the same bits everywhere. The order of the
// solve is the tiles', so the bits are those of one process on any number of ranks.
//
// Today the state is replicated: the end of each pass sends every rank's records to all
// (O(N) a pass), and the hub, the kinematic rule and the mixing are done by every rank.
// Ranks that own their rows' state alone are the next step (docs/architecture.md).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/ranks.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

namespace cdpowder {

struct ColouredPass;
struct PartSums;
struct TileOrder;

class TileRanks {
 public:
  /// Plans a tiled step's passes for this job's ranks: which rank solves which tile, and the
  /// messages after each phase. Inactive (every rank solves every part, nothing is sent) in a
  /// job of one rank or for a step that is not tiled (`tiles` null). Needs the records in tile
  /// order (`order`, tile_order.hpp): a tile's records are its part's range of places.
  void plan(const StepTiles* tiles, const ColouredPass& pass, const TileOrder& order);

  [[nodiscard]] bool active() const { return active_; }

  /// The parts of phase `phase` this rank solves (when active).
  [[nodiscard]] std::span<const std::uint32_t> phase_parts(std::size_t phase) const {
    return mine_[phase];
  }

  /// The tiles' parts this rank solves, in part order (when active).
  [[nodiscard]] std::span<const std::uint32_t> own_parts() const {
    return rank_parts_[static_cast<std::size_t>(rank_)];
  }

  /// per_part[p] of every rank's own tiles' parts p to every rank (when active): a value per
  /// part that its rank computed, such as a piece's sums of the kinematic rule. T is copied
  /// as bytes.
  template <typename T>
  void share_parts(std::vector<T>& per_part) {
    static_assert(std::is_trivially_copyable_v<T>);
    share_part_bytes(std::as_writable_bytes(std::span<T>(per_part)), sizeof(T));
  }

  /// After phase `phase` (which this rank solved its parts of): the rows it wrote go to the
  /// ranks that hold them, and the rows others wrote come in.
  void after_phase(std::size_t phase, VelocityCache& velocities);

  /// Whether every rank holds the same records (since the step began, or since the last
  /// share_records): the hub may run.
  [[nodiscard]] bool records_shared() const { return shared_; }

  /// Every rank's own rows to every rank.
  void share_records(VelocityCache& velocities);

  /// The end of a pass: the records (share_records, if not shared) and the sums of every
  /// rank's tiles to every rank. The tiles' actions wait for share_actions: nothing reads
  /// another rank's actions until the mixing or the end of the solve.
  void share_pass(std::vector<PartSums>& part_sums, VelocityCache& velocities);

  /// The contact actions of every rank's tiles to every rank, when they changed since the
  /// last time (a pass ran): before a mixing and at the end of the solve.
  void share_actions(Contacts& contacts, const ColouredPass& pass);

 private:
  /// share_parts on the bytes of per_part, `size` bytes a part.
  void share_part_bytes(std::span<std::byte> per_part, std::size_t size);

  /// A message after a phase: rows of records to or from one rank.
  struct RowMessage {
    int peer = 0;
    std::vector<std::uint32_t> rows;
    std::vector<SphereVelocity> buffer;
  };

  void pack_rows(std::span<const std::uint32_t> rows, const VelocityCache& velocities,
                 SphereVelocity* out) const;
  void unpack_rows(std::span<const std::uint32_t> rows, const SphereVelocity* in,
                   VelocityCache& velocities) const;
  /// The records of the spheres of `rows`.
  [[nodiscard]] std::size_t row_records(std::span<const std::uint32_t> rows) const;
  /// The contact actions of part p: its batched pairs, then its sequential group (overflow
  /// pairs and walls).
  [[nodiscard]] static std::size_t part_actions(const ColouredPass& pass, std::uint32_t part);

  bool active_ = false;
  bool shared_ = true;
  bool actions_shared_ = true;
  int rank_ = 0;
  int ranks_ = 1;
  TileGrid grid_;
  std::vector<std::uint32_t> part_start_;  ///< TileOrder::part_start of the step
  std::vector<std::uint32_t> row_parts_;   ///< row j's parts: [j nx, (j + 1) nx), tile order
  std::vector<int> row_owner_;             ///< the rank that solves row j's tiles
  std::vector<std::vector<std::uint32_t>> rank_rows_;   ///< each rank's rows
  std::vector<std::vector<std::uint32_t>> rank_parts_;  ///< each rank's tiles' parts
  std::array<std::vector<std::uint32_t>, kTilePhases> mine_;
  std::array<std::vector<RowMessage>, kTilePhases> sends_;
  std::array<std::vector<RowMessage>, kTilePhases> receives_;
  // scratch of the gathers: bytes of each rank's share, and the typed buffers
  std::vector<int> counts_;
  std::vector<SphereVelocity> my_records_, all_records_;
  std::vector<ContactAction> my_actions_, all_actions_;
  std::vector<PassSums> my_sums_, all_sums_;
  std::vector<std::byte> my_bytes_, all_bytes_;
};

}  // namespace cdpowder
