// coloured_sweep.cpp — batches of independent pair contacts solved side by side
// (coloured_sweep.hpp). The lane arithmetic is solve_pair's, operation for operation
// (Eigen's 3-vector dot products sum left to right, its cross products are the textbook
// formula), with the kernel's two branches computed in every lane and selected: the same
// bits as solve_pair, contact by contact (coloured_kernel.inc). The kernel is compiled twice:
// for SSE2 (2 lanes per register, the x86-64 baseline without -march flags) and for AVX2
// (4 lanes), chosen at run time. Neither uses fused multiply-add (-ffp-contract=off), so
// the results do not depend on the machine.
#include "cdpowder/solver/coloured_sweep.hpp"

#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/lanes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <type_traits>

namespace cdpowder {

// The kernel for SSE2 (the x86-64 baseline, 2 lanes per register) and AVX2 (4 lanes, chosen
// at run time): the same IEEE operations on the same operands, so the same bits.
#define CDP_LANE_CODE "cdpowder/solver/coloured_kernel.inc"
#include "cdpowder/solver/lanes_instantiate.inc"

void build_batches(const Contacts& contacts, const VelocityCache& velocities,
                   ColouredSweep& sweep) {
  const PairColouring& colouring = sweep.colouring;
  const std::size_t colours = colouring.colours();
  sweep.batches.clear();
  sweep.colour_batches.assign(colours + 1, 0);
  for (std::size_t c = 0; c < colours; ++c) {
    for (std::uint32_t m = colouring.colour_start[c]; m < colouring.colour_start[c + 1];
         m += kBatchLanes) {
      PairBatch& batch = sweep.batches.emplace_back();
      batch.lanes = std::min<std::uint32_t>(kBatchLanes, colouring.colour_start[c + 1] - m);
      for (std::uint32_t l = 0; l < batch.lanes; ++l) {
        const ContactIndex k = colouring.members[m + l];
        const PairProblem& p = contacts.pairs[k];
        const SphereVelocity& a = velocities.spheres[p.a];
        const SphereVelocity& b = velocities.spheres[p.b];
        batch.pair[l] = k;
        batch.a[l] = p.a;
        batch.b[l] = p.b;
        batch.nx[l] = p.normal.x();
        batch.ny[l] = p.normal.y();
        batch.nz[l] = p.normal.z();
        batch.gap_rate[l] = p.gap_rate;
        batch.lever_a[l] = p.lever_a;
        batch.lever_b[l] = p.lever_b;
        batch.inv_dt_w_n[l] = p.inv_dt_w_n;
        batch.inv_dt_w_t[l] = p.inv_dt_w_t;
        batch.inv_dt_w_r[l] = p.inv_dt_w_r;
        batch.cohesion[l] = p.cohesion;
        batch.mu[l] = p.mu;
        batch.roll_cap[l] = p.roll_cap;
        batch.twist_cap[l] = p.twist_cap;
        const detail::ModeBlock block = pair_mode_block(p, a, b);
        batch.coupling[l] = block.coupling;
        batch.inv_r_sq[l] = block.inv_r_sq;
        batch.mass_a[l] = a.dt_inverse_mass;
        batch.inertia_a[l] = a.dt_inverse_inertia;
        batch.mass_b[l] = b.dt_inverse_mass;
        batch.inertia_b[l] = b.dt_inverse_inertia;
      }
    }
    sweep.colour_batches[c + 1] = static_cast<std::uint32_t>(sweep.batches.size());
  }
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  sweep.sequential.assign(colouring.overflow.begin(), colouring.overflow.end());
  for (std::size_t w = 0; w < contacts.walls.size(); ++w) {
    sweep.sequential.push_back(n_pairs + static_cast<ContactIndex>(w));
  }
  sweep.group_order.resize(colours + 1);
  std::iota(sweep.group_order.begin(), sweep.group_order.end(), std::uint32_t{0});
}

namespace {

/// v[i] = old v[from[i]]
template <typename T>
void gather_into(std::vector<T>& v, const std::vector<ContactIndex>& from,
                 std::vector<T>& scratch) {
  scratch.resize(v.size());
  for (std::size_t i = 0; i < from.size(); ++i) scratch[i] = v[from[i]];
  v.swap(scratch);
}

/// v[from[i]] = old v[i]
template <typename T>
void scatter_back(std::vector<T>& v, const std::vector<ContactIndex>& from,
                  std::vector<T>& scratch) {
  scratch.resize(v.size());
  for (std::size_t i = 0; i < from.size(); ++i) scratch[from[i]] = v[i];
  v.swap(scratch);
}

}  // namespace

void prepare_coloured_sweep(Contacts& contacts, const VelocityCache& velocities,
                            ColouredSweep& sweep, std::size_t chunk) {
  PairColouring& colouring = sweep.colouring;
  colour_pairs(contacts.pairs, velocities.spheres.size(), kMaxColours, chunk, colouring,
               sweep.masks);
  // store the pairs in the order the batches visit them, overflow last
  std::vector<ContactIndex>& from = sweep.storage_index;
  from.assign(colouring.members.begin(), colouring.members.end());
  from.insert(from.end(), colouring.overflow.begin(), colouring.overflow.end());
  gather_into(contacts.pairs, from, sweep.pair_scratch);
  gather_into(contacts.pair_actions, from, sweep.action_scratch);
  gather_into(contacts.pair_cohesive, from, sweep.flag_scratch);
  std::iota(colouring.members.begin(), colouring.members.end(), ContactIndex{0});
  std::iota(colouring.overflow.begin(), colouring.overflow.end(),
            static_cast<ContactIndex>(colouring.members.size()));
  build_batches(contacts, velocities, sweep);
}

void restore_storage_order(Contacts& contacts, ColouredSweep& sweep) {
  const std::vector<ContactIndex>& from = sweep.storage_index;
  if (from.size() != contacts.pairs.size()) return;  // not prepared
  scatter_back(contacts.pairs, from, sweep.pair_scratch);
  scatter_back(contacts.pair_actions, from, sweep.action_scratch);
  scatter_back(contacts.pair_cohesive, from, sweep.flag_scratch);
  sweep.storage_index.clear();
}

void order_groups(ColouredSweep& sweep, VisitOrder policy, Rng& rng) {
  const std::vector<std::uint32_t>& chunk_colours = sweep.colouring.chunk_colours;
  const auto chunks = static_cast<std::uint32_t>(chunk_colours.size() - 1);
  const bool shuffle = policy != VisitOrder::Fixed;
  // the chunks and the sequential group (id `chunks`) in a random order, and each chunk's
  // colours in a random order
  sweep.chunk_order.resize(chunks + 1);
  std::iota(sweep.chunk_order.begin(), sweep.chunk_order.end(), std::uint32_t{0});
  if (shuffle) shuffle_indices(std::span<std::uint32_t>(sweep.chunk_order), rng);
  sweep.group_order.clear();
  for (const std::uint32_t chunk : sweep.chunk_order) {
    if (chunk == chunks) {
      sweep.group_order.push_back(static_cast<std::uint32_t>(sweep.colours()));
      continue;
    }
    const std::size_t first = sweep.group_order.size();
    for (std::uint32_t c = chunk_colours[chunk]; c < chunk_colours[chunk + 1]; ++c) {
      sweep.group_order.push_back(c);
    }
    if (shuffle) {
      shuffle_indices(std::span<std::uint32_t>(sweep.group_order).subspan(first), rng);
    }
  }
}

bool allow_avx2_kernel(bool allowed) {
  return lanes::allow_avx2(allowed);
}

namespace {

using SolveBatches = void (*)(const PairBatch*, std::uint32_t, std::uint32_t, SphereVelocity*,
                              ContactAction*, SweepSums&, BatchVisits*);

/// The kernel for this CPU, with torques or without (ColouredSweep::torques).
SolveBatches batch_kernel(bool torques) {
  return torques ? CDP_LANES_FOR_CPU(solve_batches<true>) : CDP_LANES_FOR_CPU(solve_batches<false>);
}

}  // namespace

void apply_pair_deltas(const ColouredSweep& sweep, const std::vector<ContactAction>& deltas,
                       const Contacts& contacts, VelocityCache& velocities) {
  using ApplyBatches = void (*)(const PairBatch*, std::uint32_t, std::uint32_t, SphereVelocity*,
                                const ContactAction*);
  const ApplyBatches apply = sweep.torques ? CDP_LANES_FOR_CPU(apply_batches<true>)
                                           : CDP_LANES_FOR_CPU(apply_batches<false>);
  // colour by colour in storage order: each sphere gets its changes in the order of the
  // scalar loop over the pairs (no sphere twice in a colour), so the same bits
  apply(sweep.batches.data(), 0, static_cast<std::uint32_t>(sweep.batches.size()),
        velocities.spheres.data(), deltas.data());
  for (const ContactIndex k : sweep.colouring.overflow) {
    apply_pair_action(contacts.pairs[k], deltas[k], velocities);
  }
}

void solve_batches_kept(const ColouredSweep& sweep, std::uint32_t first, std::uint32_t last,
                        VelocityCache& velocities, Contacts& contacts, BatchVisits* record) {
  SweepSums unused;
  batch_kernel(sweep.torques)(sweep.batches.data(), first, last, velocities.spheres.data(),
                              contacts.pair_actions.data(), unused, record);
}

SweepSums run_coloured_sweep(Contacts& contacts, VelocityCache& velocities,
                             const ColouredSweep& sweep) {
  SweepSums sums;
  const std::size_t colours = sweep.colours();
  SphereVelocity* const spheres = velocities.spheres.data();
  ContactAction* const actions = contacts.pair_actions.data();
  const SolveBatches solve = batch_kernel(sweep.torques);
  for (const std::uint32_t group : sweep.group_order) {
    if (group == colours) {
      for (const ContactIndex k : sweep.sequential) visit_contact(k, contacts, velocities, sums);
      continue;
    }
    solve(sweep.batches.data(), sweep.colour_batches[group], sweep.colour_batches[group + 1],
          spheres, actions, sums, nullptr);
  }
  return sums;
}

}  // namespace cdpowder
