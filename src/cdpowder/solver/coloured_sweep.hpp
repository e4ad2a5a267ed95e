// coloured_sweep.hpp — the coloured sweep kernel (solver.kernel = "coloured", the default;
// docs/performance.md "Coloured kernel"). The step's sphere–sphere contacts are
// coloured (colouring.hpp) and each colour is gathered into batches of kBatchLanes contacts
// in structure-of-arrays form, solved side by side with the same arithmetic per contact as
// solve_pair: a coloured sweep is an exact reordering of a scalar sweep. Overflow pairs and
// all wall contacts (the piston couples its contacts through one velocity) form one more
// group, solved one by one with the scalar kernels. A sweep visits the groups in an order
// drawn from the sweep-order stream (physics.md §7.1, at the level of colours).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/solver/colouring.hpp"
#include "cdpowder/solver/settings.hpp"
#include "cdpowder/solver/sweep_sums.hpp"
#include "cdpowder/solver/velocity_cache.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace cdpowder {

inline constexpr int kBatchLanes = 4;

/// kBatchLanes pair contacts of one colour, the frozen data of PairProblem lane by lane.
/// Unused lanes (the last batch of a colour) hold zeros and touch no sphere.
struct alignas(64) PairBatch {
  using Lanes = std::array<double, kBatchLanes>;
  Lanes nx{}, ny{}, nz{};
  Lanes gap_rate{}, lever_a{}, lever_b{};
  Lanes inv_dt_w_n{}, inv_dt_w_t{}, inv_dt_w_r{};
  Lanes cohesion{}, mu{}, roll_cap{}, twist_cap{};
  Lanes coupling{};                                    ///< Δt c of pair_mode_block
  Lanes inv_r_sq{};                                    ///< 1/r_eff²
  Lanes mass_a{}, inertia_a{}, mass_b{}, inertia_b{};  ///< Δt/m and Δt/I of both spheres
  std::array<ContactIndex, kBatchLanes> pair{};
  std::array<BodyIndex, kBatchLanes> a{}, b{};
  std::uint32_t lanes = 0;  ///< lanes in use, 1..kBatchLanes
};

/// What the kBatchLanes visits of a batch report to the sweep sums, kept to be added in
/// visiting order after a sweep on several threads (closed_normal as in sweep_sums.hpp).
struct alignas(64) BatchVisits {
  std::array<double, kBatchLanes> change_sq{};
  std::array<double, kBatchLanes> closed_normal{};
};

/// The step's colours, batches and group order; reused from step to step.
struct ColouredSweep {
  PairColouring colouring;
  std::vector<std::uint64_t> masks;           ///< scratch of the colouring
  std::vector<PairBatch> batches;             ///< colour by colour
  std::vector<std::uint32_t> colour_batches;  ///< colour c: batches [cb[c], cb[c + 1])
  std::vector<ContactIndex> sequential;       ///< overflow pairs, then walls (n_pairs + w)
  std::vector<std::uint32_t> group_order;     ///< colours 0..C−1 and C = the sequential group
  std::vector<std::uint32_t> chunk_order;     ///< scratch of order_groups
  std::vector<ContactIndex> storage_index;  ///< pair i is stored pair storage_index[i] of the step
  std::vector<PairProblem> pair_scratch;
  std::vector<ContactAction> action_scratch;
  std::vector<std::uint8_t> flag_scratch;
  /// false when no contact of the step has a rolling or torsion threshold and no torque is
  /// non-zero: the kernels then leave the torques alone (they stay +0, the bits are the same)
  bool torques = true;
  std::vector<ContactAction> deltas;  ///< scratch of the mixing: pair action changes

  [[nodiscard]] std::size_t colours() const {
    return colour_batches.empty() ? 0 : colour_batches.size() - 1;
  }
};

/// Colours the step's pairs greedily (chunks of kColourChunk contacts), stores them in the
/// order the sweep visits them (so a sweep streams through the pairs and their actions;
/// restore_storage_order undoes it) and builds the batches.
void prepare_coloured_sweep(Contacts& contacts, const VelocityCache& velocities,
                            ColouredSweep& sweep, std::size_t chunk = kColourChunk);

/// Puts the pairs, their actions and flags back in storage order (sorted by sphere pair), as
/// the rest of the step expects them.
void restore_storage_order(Contacts& contacts, ColouredSweep& sweep);

/// Builds the batches and the sequential group from sweep.colouring (set by the caller).
void build_batches(const Contacts& contacts, const VelocityCache& velocities, ColouredSweep& sweep);

/// Group order: storage order for VisitOrder::Fixed, else the chunks (and the sequential
/// group) in a fresh random order from `rng`, each chunk's colours in a random order.
void order_groups(ColouredSweep& sweep, VisitOrder policy, Rng& rng);

/// Lets the sweep use the AVX2 kernel where the CPU has it (default, unless the environment
/// says CDPOWDER_KERNEL_ISA=sse2), or keeps it on SSE2; both give the same bits. Returns
/// whether AVX2 is used.
bool allow_avx2_kernel(bool allowed);

/// Moves the velocity cache by the pair action changes deltas[k] (pairs stored in colour order,
/// as during the solve), as apply_pair_action over the pairs in storage order would: the
/// batches 4 lanes at a time, then the overflow pairs. The same bits.
void apply_pair_deltas(const ColouredSweep& sweep, const std::vector<ContactAction>& deltas,
                       const Contacts& contacts, VelocityCache& velocities);

/// Solves the batches [first, last) of one colour and writes their visits to
/// record[0, last − first) instead of adding them to sums (a thread's share of a colour).
void solve_batches_kept(const ColouredSweep& sweep, std::uint32_t first, std::uint32_t last,
                        VelocityCache& velocities, Contacts& contacts, BatchVisits* record);

/// One sweep over the groups in sweep.group_order.
SweepSums run_coloured_sweep(Contacts& contacts, VelocityCache& velocities,
                             const ColouredSweep& sweep);

}  // namespace cdpowder
