// tile_ranks.hpp — a tiled step's passes shared among the ranks of an MPI job
// (core/ranks.hpp; docs/architecture.md, "Ranks (MPI)").
//
// Every rank holds the whole state and does the whole step, except the tiles of the colour
// phases: rank r solves the tiles of a strip of whole tile rows [j0, j1), the same tiles in
// every phase. A tile's contacts write the spheres of its own row and of the next (the ghost
// row of the rank below), so after a phase the records that one neighbour wrote and the other
// reads go between them: of the boundary rows, the spheres that the contacts across the
// boundary touch (a few in a row), one message per pair of neighbours. Before
// the hub (its contacts touch any tile) its spheres' records go to every rank; at the end of a
// pass the tiles' sums; at the end of the solve every rank's records and actions, so everything
// after the solve runs on the same bits everywhere. The order of the
// solve is the tiles', so the bits are those of one process on any number of ranks.
//
// Today the state is replicated, and the hub is solved by every rank on its spheres' records,
// gathered before it (a few spheres); every record goes to every rank once a step, at the end
// of the solve. The kinematic rule, the mixing (each tile with its overflow pairs and walls)
// and the split piston run on each rank's own tiles (their sums shared with share_parts and
// share_piston_pieces), the hub's mixing on every rank. Ranks that own their rows' state alone
// are the next step (docs/architecture.md).
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
  /// `contacts` are the solve's (the actions in colour order, the spheres named by their
  /// places): the hub's spheres are those of the hub's contacts.
  void plan(const StepTiles* tiles, const ColouredPass& pass, const TileOrder& order,
            const Contacts& contacts);

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
    share_bytes(std::as_writable_bytes(std::span<T>(per_part)), sizeof(T), rank_parts_);
  }

  /// The split piston's pieces (split_piston.hpp: the tiles with piston contacts, in tile
  /// order) this rank solves: its own tiles' (when active).
  [[nodiscard]] std::span<const std::uint32_t> own_piston_pieces() const {
    return rank_piston_pieces_[static_cast<std::size_t>(rank_)];
  }

  /// After this rank solved its piston pieces: their spheres' records to the rank that holds
  /// their row as its ghost row (the owner of the row below), and those of the row above from
  /// its owner.
  void after_piston(VelocityCache& velocities);

  /// per_piece[p] of every rank's own piston pieces p to every rank (when active), as
  /// share_parts does for parts.
  template <typename T>
  void share_piston_pieces(std::vector<T>& per_piece) {
    static_assert(std::is_trivially_copyable_v<T>);
    share_bytes(std::as_writable_bytes(std::span<T>(per_piece)), sizeof(T), rank_piston_pieces_);
  }

  /// After phase `phase` (which this rank solved its parts of): the records it wrote that a
  /// neighbour reads go to it, and those a neighbour wrote that this rank reads come in.
  void after_phase(std::size_t phase, VelocityCache& velocities);

  /// Every rank's own rows to every rank.
  void share_records(VelocityCache& velocities);

  /// Before the hub: the records of the hub's spheres (its contacts') from the ranks whose rows
  /// hold them to every rank, which then solves the hub on them; each rank then solves its
  /// own tiles' piston contacts (run_split_piston).
  /// Between passes a rank's records are current for its own rows and for the spheres of its
  /// ghost row that its tiles' contacts touch, alone.
  void share_hub_records(VelocityCache& velocities);

  /// The end of a pass: the sums of every rank's tiles to every rank. The tiles' actions and
  /// records wait for share_solution: nothing reads another rank's tiles until then.
  void share_pass(std::vector<PartSums>& part_sums);

  /// The end of the solve: every rank's records and actions to every rank.
  void share_solution(Contacts& contacts, const ColouredPass& pass, VelocityCache& velocities);

  /// The contact actions of every rank's tiles to every rank, when they changed since the
  /// last time (a pass ran): at the end of the solve, and for the relative-change rule after
  /// every pass.
  void share_actions(Contacts& contacts, const ColouredPass& pass);

 private:
  /// The places of the hub's pairs' spheres, by the rank whose rows hold them
  /// (rank_hub_places_).
  void plan_hub(const ColouredPass& pass, const Contacts& contacts,
                const std::vector<std::uint32_t>& part_row);
  /// items[i] (`size` bytes each) of every rank r's items i ∈ rank_items[r] to every rank.
  void share_bytes(std::span<std::byte> items, std::size_t size,
                   const std::vector<std::vector<std::uint32_t>>& rank_items);
  /// Each rank's piston pieces (rank_piston_pieces_).
  void plan_piston(const ColouredPass& pass, const Contacts& contacts,
                   const std::vector<std::uint32_t>& part_row);
  /// The part of the sphere at `place` (part_start_).
  [[nodiscard]] std::uint32_t part_of_place(std::uint32_t place) const;

  /// A message after a phase or the split piston: the records of single spheres (their
  /// places, ascending) to or from one rank.
  struct PlaceMessage {
    int peer = 0;
    std::vector<std::uint32_t> places;
    std::vector<SphereVelocity> buffer;
  };

  /// Each phase's messages (sends_, receives_): the records of this rank's first row that its
  /// tiles write and the rank below reads, and those of its ghost row that either side writes
  /// and the other reads.
  void plan_phase_messages(const ColouredPass& pass, const Contacts& contacts,
                           const std::vector<std::uint32_t>& part_row);
  /// Places by phase: entry f for phase f, the last entry for any phase; each ascending.
  using PhaseWrites = std::array<std::vector<std::uint32_t>, kTilePhases + 1>;
  /// The spheres of tile row `row` that the tiles of tile row `tile_row` write, by phase. A
  /// tile's contacts write its own row and the next (docs/architecture.md).
  PhaseWrites phase_writes(const ColouredPass& pass, const Contacts& contacts,
                           const std::vector<std::uint32_t>& part_row, std::uint32_t tile_row,
                           std::uint32_t row);
  /// Adds `places` to the message of `list` to `peer` (a new one if there is none).
  static void add_places(std::vector<PlaceMessage>& list, int peer,
                         const std::vector<std::uint32_t>& places);
  /// Appends the places of the spheres that part `part`'s contacts write in a pass or a
  /// mixing: its batched pairs', its sequential group's, its overflow pairs' and its walls'.
  static void append_part_spheres(const ColouredPass& pass, const Contacts& contacts,
                                  std::uint32_t part, std::vector<std::uint32_t>& places);
  /// Sends the records of `sends` and takes those of `receives` into `velocities`.
  static void exchange_places(std::vector<PlaceMessage>& sends, std::vector<PlaceMessage>& receives,
                              int tag, VelocityCache& velocities);
  void pack_rows(std::span<const std::uint32_t> rows, const VelocityCache& velocities,
                 SphereVelocity* out) const;
  void unpack_rows(std::span<const std::uint32_t> rows, const SphereVelocity* in,
                   VelocityCache& velocities) const;
  /// The records of the spheres of `rows`.
  [[nodiscard]] std::size_t row_records(std::span<const std::uint32_t> rows) const;
  /// The contact actions of part p: its batched pairs, then its sequential group (overflow
  /// pairs and walls).
  [[nodiscard]] static std::size_t part_actions(const ColouredPass& pass, std::uint32_t part);
  /// Every rank's tiles' actions to every rank.
  void gather_actions(Contacts& contacts, const ColouredPass& pass);

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
  /// each rank's split-piston pieces (the pieces of its tiles), ascending
  std::vector<std::vector<std::uint32_t>> rank_piston_pieces_;
  std::vector<PlaceMessage> piston_sends_, piston_receives_;
  std::array<std::vector<std::uint32_t>, kTilePhases> mine_;
  std::array<std::vector<PlaceMessage>, kTilePhases> sends_;
  std::array<std::vector<PlaceMessage>, kTilePhases> receives_;
  // scratch of the gathers: bytes of each rank's share, and the typed buffers
  std::vector<int> counts_;
  std::vector<SphereVelocity> my_records_, all_records_;
  std::vector<ContactAction> my_actions_, all_actions_;
  /// each rank's hub spheres: the places in its rows of the hub's spheres, ascending
  std::vector<std::vector<std::uint32_t>> rank_hub_places_;
  std::vector<std::byte> my_bytes_, all_bytes_;
  /// scratch of phase_writes: a bit a phase for each place (clear between calls), and the
  /// places marked
  std::vector<std::uint8_t> marks_;
  std::vector<std::uint32_t> touched_;
};

}  // namespace cdpowder
