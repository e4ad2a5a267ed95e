// coloured_pass.hpp — the coloured pass kernel (solver.kernel = "coloured", the default;
// docs/lab/2026-11-25-coloured-kernel.md). The step's sphere–sphere contacts are
// coloured (colouring.hpp) and each colour is gathered into batches of kBatchLanes contacts
// in structure-of-arrays form, solved side by side with the same arithmetic per contact as
// solve_pair: a coloured pass is an exact reordering of a scalar pass. Overflow pairs and
// wall contacts (the piston couples its contacts through one velocity) form one more group,
// solved one by one with the scalar kernels, except its bottom-wall contacts: no two share a
// sphere, so they are batched too (WallBatchPair) and solved side by side with solve_wall's
// arithmetic, in their place in the group. A pass visits the groups in an order drawn from
// the pass-order stream (physics.md §7.1, at the level of colours).
// When the step is tiled (tiles.hpp) the contacts come in parts (the tiles in pass order, then
// the hub), each with its own colours and sequential group; a pass visits the four phases'
// tiles and the hub in the step's slot order, and adds each part's visits to sums of its own,
// which are then added in part order (PassSums::add_part), so the bits do not depend on
// whether a phase's tiles ran one after the other or side by side.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/solver/nlgs/colouring.hpp"
#include "cdpowder/solver/nlgs/pass_sums.hpp"
#include "cdpowder/solver/nlgs/split_piston.hpp"
#include "cdpowder/solver/nlgs/tile_ranks.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "cdpowder/solver/settings.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace cdpowder {

namespace lanes {
enum class Isa : std::uint8_t;  // lanes.hpp
}  // namespace lanes

/// Contacts in a batch: the unit the colours are cut into, whatever the lane width.
inline constexpr int kBatchLanes = 4;
/// Lanes of a BatchPair: two batches.
inline constexpr int kPairLanes = 2 * kBatchLanes;
/// A SphereVelocity and a ContactAction are 8 doubles each (one 64-byte line).
inline constexpr std::uint32_t kRecordDoubles = 8;

/// Two consecutive batches of kBatchLanes pair contacts of one colour side by side (lanes 0–3
/// batch 2i, lanes 4–7 batch 2i + 1), the frozen data of PairProblem lane by lane: a field of
/// both is one register of eight on AVX-512, and a batch's is half of it on SSE2 and AVX2.
/// A colour starts at a new pair; with an odd number of batches its last pair's second batch
/// is padding (no lane in use) that repeats the first, lane for lane. Unused lanes of a batch
/// (a colour's last) repeat a used lane of the same register pair (lanes 0–1 or 2–3; lane 0
/// where the pair has none). Either way the kernel solves a contact twice side by side from
/// the same records into the same records, the same bits (a repeated store), and leaves the
/// repeats out of its sums.
struct alignas(64) BatchPair {
  using Lanes = std::array<double, kPairLanes>;
  Lanes nx{}, ny{}, nz{};
  Lanes gap_rate{}, lever_a{}, lever_b{};
  Lanes inv_dt_w_n{}, inv_dt_w_t{}, inv_dt_w_r{};
  Lanes cohesion{}, mu{}, roll_cap{}, twist_cap{};
  Lanes coupling{};                                    ///< Δt c of pair_mode_block
  Lanes inv_r_sq{};                                    ///< 1/r_eff²
  Lanes mass_a{}, inertia_a{}, mass_b{}, inertia_b{};  ///< Δt/m and Δt/I of both spheres
  /// the lanes' records as offsets in doubles (index × kRecordDoubles): action x_row of
  /// pair_actions, spheres a_row and b_row of the velocity cache (one load and an
  /// addressing mode per record in the kernel)
  std::array<std::uint32_t, kPairLanes> x_row{}, a_row{}, b_row{};
  std::array<std::uint32_t, 2> lanes{};  ///< lanes in use of each batch, 0..kBatchLanes
};

/// Bottom-wall contacts side by side, as BatchPair holds pairs: WallProblem's frozen data and
/// its sphere's Δt/m and Δt/I lane by lane, two batches of kBatchLanes, with BatchPair's rules
/// for unused lanes and padding batches. No two bottom-wall contacts share a sphere (a sphere
/// has one at most) and the wall does not move, so any of them may be solved side by side. The
/// fields the modes read have ModeBlock's (and BatchPair's) names.
struct alignas(64) WallBatchPair {
  using Lanes = std::array<double, kPairLanes>;
  Lanes nx{}, ny{}, nz{};
  Lanes gap_rate{}, radius{};
  Lanes inv_dt_w_n{}, inv_dt_w_t{}, inv_dt_w_r{};
  Lanes cohesion{}, mu{}, roll_cap{}, twist_cap{};
  Lanes coupling{};         ///< −R Δt/I, solve_wall's Δt c
  Lanes inv_r_sq{};         ///< 1/R²
  Lanes mass{}, inertia{};  ///< Δt/m and Δt/I of the sphere
  /// offsets in doubles: action x_row of wall_actions, sphere s_row of the velocity cache
  std::array<std::uint32_t, kPairLanes> x_row{}, s_row{};
  std::array<std::uint32_t, 2> lanes{};  ///< lanes in use of each batch, 0..kBatchLanes
};

/// What a step's colouring, storage order and batch rows are built from: the pairs' spheres and
/// the wall contacts (sphere and wall) in storage order, each sphere's part (its tile) and the
/// colouring chunk. They are a function of these alone, so a step whose inputs match the
/// last build's (most steps: the candidate lists are reused and contacts seldom open or close
/// from one step to the next) keeps them and only refills the batches' values: the same bits.
class ColouringInputs {
 public:
  /// Whether the pairs and walls (in storage order), the spheres' parts `sphere_part` and
  /// `chunk` are those recorded; the pairs compared in pieces on `runner` when given.
  [[nodiscard]] bool match(const std::vector<PairProblem>& pairs,
                           const std::vector<WallProblem>& walls,
                           std::span<const std::uint32_t> sphere_part, std::size_t chunk,
                           PieceRunner* runner = nullptr) const;
  /// Records them, after a build from them.
  void record(const std::vector<PairProblem>& pairs, const std::vector<WallProblem>& walls,
              std::span<const std::uint32_t> sphere_part, std::size_t chunk);

  /// After the colouring or the batches were changed by other means.
  void forget() { recorded_ = false; }

 private:
  std::vector<std::uint64_t> pairs_;  ///< contact_key (action_cache.hpp): a << 32 | b
  std::vector<std::uint64_t> walls_;  ///< contact_key: wall kind << 32 | sphere
  std::vector<std::uint32_t> sphere_part_;
  std::size_t chunk_ = 0;
  bool recorded_ = false;
};

/// A part's sums of a pass, on a cache line of its own (threads write them side by side).
struct alignas(64) PartSums {
  PassSums sums;
};

/// The step's colours, batches and group order; reused from step to step.
struct ColouredPass {
  PairColouring colouring;
  std::vector<std::uint64_t> masks;  ///< scratch of the colouring
  /// colour by colour; batch i is half i % 2 of batch_pairs[i / 2]
  std::vector<BatchPair> batch_pairs;
  /// colour c: batches [cb[c], cb[c + 1]), cb[c] even (with its padding batch, if any)
  std::vector<std::uint32_t> colour_batches;
  /// part p's overflow pairs, then its walls (n_pairs + w): sequential[ps[p], ps[p + 1])
  std::vector<ContactIndex> sequential;
  std::vector<std::uint32_t> part_sequential{0, 0};
  /// part p's sequential group holds its bottom-wall contacts at sequential[bottom_walls[p].first,
  /// bottom_walls[p].second), right after its overflow pairs: they are solved side by side as
  /// wall batches [part_wall_batches[p], part_wall_batches[p + 1]) of wall_batch_pairs (even,
  /// with padding), the others of the group one by one
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bottom_walls{{0, 0}};
  std::vector<WallBatchPair> wall_batch_pairs;
  std::vector<std::uint32_t> part_wall_batches{0, 0};
  /// colours 0..C−1, and C + p = part p's sequential group; part p's groups are
  /// group_order[part_groups[p], part_groups[p + 1])
  std::vector<std::uint32_t> group_order;
  std::vector<std::uint32_t> part_groups{0, 0};
  std::vector<std::uint32_t> wall_part;  ///< each wall contact's part (empty: all in part 0)
  /// phase f runs parts [phase_parts[f], phase_parts[f + 1]) side by side; the parts from
  /// phase_parts[kTilePhases] on (the hub of a tiled step) run alone, on the caller
  std::array<std::uint32_t, kTilePhases + 1> phase_parts{0, 1, 1, 1, 1};
  /// The parts in the order of their tiles, row by row (StepTiles::part_of_tile), then the
  /// hub: the order in which a loop over every part hands them to the threads. A phase hands
  /// its tiles out in tile order too, and TileThreads gives each thread a contiguous range of
  /// pieces first, so a thread takes the same rows of tiles in every stage of a pass (the
  /// phases, the mixing, the kinematic rule's pieces) and a tile's data stays in its core's
  /// cache. Which thread takes a part changes no bit.
  std::vector<std::uint32_t> strip_order{0};
  /// the order of a pass's slots: slot f < kTilePhases runs phase f, slot kTilePhases the hub;
  /// drawn per step with the groups (order_groups), so no phase and not the hub always comes
  /// first (a fixed order would sweep the cell in one direction every pass)
  std::array<std::uint32_t, kTilePhases + 1> slot_order{0, 1, 2, 3, 4};
  std::vector<std::uint32_t> chunk_order;  ///< scratch of order_groups
  std::vector<ContactIndex> part_order;    ///< scratch: the pairs part by part
  std::vector<std::uint32_t> part_start;   ///< scratch: part p's pairs start in part_order
  std::vector<std::uint32_t> part_next;    ///< scratch of the counting sorts (group_by_part)
  std::vector<std::uint32_t> pair_part;    ///< scratch: each pair's part
  std::vector<std::uint32_t> wall_start;   ///< scratch: part p's walls start in wall_order
  std::vector<ContactIndex> wall_order;    ///< scratch: the walls part by part
  /// The walls by their sphere's part, the piston's included (which wall_part gives the hub),
  /// each part's in storage order: part p's are mixing_walls[mixing_wall_start[p],
  /// mixing_wall_start[p + 1]). A tiled step's mixing keeps each tile's walls together in
  /// this order (tile_solve.hpp); they touch its spheres alone, and the piston.
  std::vector<ContactIndex> mixing_walls;
  std::vector<std::uint32_t> mixing_wall_start{0, 0};
  /// scratch of a tiled step's mixing: each part's change of the piston's velocity
  std::vector<double> part_piston_change;
  /// each part's sums of the last pass (run_coloured_pass), added in part order
  mutable std::vector<PartSums> part_sums;
  std::vector<ContactIndex> storage_index;  ///< pair i is stored pair storage_index[i] of the step
  /// whether Contacts holds the pairs' actions in colour order (from prepare_coloured_pass to
  /// restore_storage_order)
  bool in_colour_order = false;
  /// the inputs of the last build of the colouring, storage_index and the batches' rows
  ColouringInputs built_from;
  /// the pairs' actions in the other order while prepare_coloured_pass and
  /// restore_storage_order reorder them; in between (the passes and the mixing) the mixing's
  /// pair action changes, since the restore writes every entry anew (one array of 64 bytes a
  /// pair less than a scratch of its own)
  std::vector<ContactAction> action_scratch;
  /// false when no contact of the step has a rolling or torsion threshold and no torque is
  /// non-zero: the pair kernels then leave the torques alone (they stay +0, the bits are the
  /// same); the bottom-wall batches always solve them, as solve_wall does
  bool torques = true;
  /// which of two kernels with the same bits the next pass runs: with open contacts rare in the
  /// last pass (≤ 1 % of its visits), the one that skips the open branch where no lane of a
  /// call needs it (coloured_kernel.inc). A hint about speed alone, so a pass taken as const
  /// updates it (run_coloured_pass), and tests may set it.
  mutable bool open_rare = false;
  /// a tiled step's piston contacts, tile by tile with the piston's mass split (not in the
  /// hub's sequential group); inactive when the step is not tiled
  SplitPiston split_piston;

  /// batches with a lane in use (the padding of colours with an odd number left out)
  [[nodiscard]] std::size_t batches() const {
    std::size_t count = 0;
    for (const BatchPair& pair : batch_pairs)
      count += (pair.lanes[0] > 0 ? 1 : 0) + (pair.lanes[1] > 0 ? 1 : 0);
    return count;
  }

  [[nodiscard]] std::size_t colours() const {
    return colour_batches.empty() ? 0 : colour_batches.size() - 1;
  }

  /// Parts of the pass (one when the step is not tiled).
  [[nodiscard]] std::size_t parts() const { return part_groups.size() - 1; }

  /// Whether the step is tiled: more than one part.
  [[nodiscard]] bool tiled() const { return parts() > 1; }

  /// Where pair k of the actions' order (the colour order during the solve) has its record:
  /// the records stay in storage order (the batches hold what the passes read of the batched
  /// pairs; a colour-order copy of the records cost 128 bytes a pair). Null where the two
  /// orders are one (no storage index: a colouring built in storage order, as tests do).
  [[nodiscard]] const ContactIndex* record_of() const {
    return storage_index.empty() ? nullptr : storage_index.data();
  }

  /// The record of pair k of the actions' order (record_of).
  [[nodiscard]] const PairProblem& pair_record(const Contacts& contacts, ContactIndex k) const {
    return pair_record_at(contacts, record_of(), k);
  }
};

/// Colours the step's pairs greedily (chunks of kColourChunk contacts), part by part when
/// `tiles` tiles the step (tiles.hpp; null or not tiled: one part), stores the pairs' actions
/// in the order the pass visits them (so a pass streams through them; restore_storage_order
/// undoes it) and builds the batches. The records and the cohesion flags stay in storage order:
/// during the solve, pair k of the colour order is ColouredPass::pair_record(contacts, k). When the
/// pairs, walls and tiles are the last build's (ColouringInputs), the colouring and the batches'
/// rows are kept and only the batches' values are filled again, part by part, on the threads of
/// `pieces` if given: those of the parts p with `solved[p]` set alone, when `solved` is not
/// empty (an MPI rank's own tiles and the hub, parts_of_rank in tiles.hpp; the others' batches
/// are not read on this rank).
void prepare_coloured_pass(Contacts& contacts, const VelocityCache& velocities, ColouredPass& pass,
                           std::size_t chunk = kColourChunk, const StepTiles* tiles = nullptr,
                           PieceRunner* pieces = nullptr,
                           std::span<const std::uint8_t> solved = {});

/// Puts the pairs' actions back in storage order (sorted by sphere pair), as the rest of the
/// step expects them; in pieces on `pieces` when there is one (run_chunks).
void restore_storage_order(Contacts& contacts, ColouredPass& pass, PieceRunner* pieces = nullptr);

/// Builds the batches and the sequential groups from pass.colouring, pass.storage_index and
/// pass.wall_part (set by the caller). The next prepare_coloured_pass colours afresh.
void build_batches(const Contacts& contacts, const VelocityCache& velocities, ColouredPass& pass);

/// Group order, part by part: storage order for VisitOrder::Fixed, else the part's chunks (and
/// its sequential group) in a fresh random order from `rng`, each chunk's colours in a random
/// order; for a tiled step then the order of the phases and the hub (slot_order).
void order_groups(ColouredPass& pass, VisitOrder policy, Rng& rng);

/// Lets the pass use kernels up to `widest` where the CPU has them (default: AVX-512, two
/// batches per register; unless the environment says CDPOWDER_KERNEL_ISA=avx2 or sse2): all
/// give the same bits. Returns whether the kernel now runs on `widest`.
bool allow_kernel_isa(lanes::Isa widest);

/// Moves the velocity cache by the pair action changes deltas[k] (in colour order, as the
/// actions during the solve), as apply_pair_action over the pairs in storage order would: the
/// batches colour by colour, a register of lanes at a time, then the overflow pairs. The same
/// bits.
void apply_pair_deltas(const ColouredPass& pass, const std::vector<ContactAction>& deltas,
                       const Contacts& contacts, VelocityCache& velocities);

/// apply_pair_deltas of part p's batches alone (the parts of a phase touch no common sphere);
/// apply_pair_deltas is every part in order and then apply_overflow_deltas.
void apply_part_deltas(const ColouredPass& pass, std::size_t part,
                       const std::vector<ContactAction>& deltas, VelocityCache& velocities);
void apply_overflow_deltas(const ColouredPass& pass, const std::vector<ContactAction>& deltas,
                           const Contacts& contacts, VelocityCache& velocities);
/// apply_overflow_deltas of part p's overflow pairs alone (they touch the spheres of its
/// batches' 2 × 2 block of tiles).
void apply_part_overflow_deltas(const ColouredPass& pass, std::size_t part,
                                const std::vector<ContactAction>& deltas, const Contacts& contacts,
                                VelocityCache& velocities);

/// Part p's groups of one pass, in pass.group_order, with sums of their own.
PassSums run_coloured_part(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                           std::size_t part);

/// One pass over the groups in pass.group_order, part by part: the phases' parts (side by
/// side on `threads` when given) and the rest (the hub, then the split piston contacts) in
/// pass.slot_order, their sums added in part order, the split piston's last: the same bits on
/// any number of threads. With `ranks` active (tile_ranks.hpp) this rank solves its own tiles
/// of each phase and shares the rows they wrote, the hub runs on its spheres' records gathered
/// from every rank, and the pass ends with every rank's tiles' sums on every rank: the same
/// bits on any number of ranks. Sets pass.open_rare for the next pass from its sums.
PassSums run_coloured_pass(Contacts& contacts, VelocityCache& velocities, const ColouredPass& pass,
                           TileThreads* threads = nullptr, TileRanks* ranks = nullptr);

}  // namespace cdpowder
