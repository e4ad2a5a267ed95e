// nlgs.cpp — the pass loop and the stopping rules.
#include "cdpowder/solver/nlgs/nlgs.hpp"

#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/nth_root.hpp"
#include "cdpowder/core/ranks.hpp"
#include "cdpowder/solver/nlgs/mixed_actions.hpp"
#include "cdpowder/solver/nlgs/tile_order.hpp"
#include "cdpowder/solver/nlgs/tile_solve.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "cdpowder/solver/nlgs/visit_contact.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <type_traits>
#include <vector>

namespace cdpowder {

namespace {

/// Passes over which the contraction ρ is measured: long enough to average out the
/// pass-to-pass noise of a random visiting order.
constexpr int kContractionWindow = 8;
static_assert(kContractionWindow <= kMaxRootDegree, "nth_root takes roots up to the 8th");
/// ρ is capped here, so the error estimate is at most 1000 × the residual.
constexpr double kMaxContraction = 0.999;

/// The last kContractionWindow + 1 values of a per-pass measure (residual, kinematic
/// change) and the contraction ρ per pass they show.
class ContractionWindow {
 public:
  /// Adds the measure of pass `pass` (1, 2, …) and returns ρ = (x_k / x_{k−w})^{1/w} over
  /// the last w = min(kContractionWindow, k − 1) passes, clamped to [0, kMaxContraction]; the
  /// root from nth_root, whose bits do not depend on the machine or its C library as pow's do.
  double add(int pass, double value) {
    recent_[static_cast<std::size_t>(pass) % recent_.size()] = value;
    const int window = std::min(kContractionWindow, pass - 1);
    if (window == 0) return kMaxContraction;
    const double earlier = recent_[static_cast<std::size_t>(pass - window) % recent_.size()];
    const double rho = earlier > 0.0 ? nth_root(value / earlier, window) : 0.0;
    return std::clamp(rho, 0.0, kMaxContraction);
  }

 private:
  std::array<double, kContractionWindow + 1> recent_{};
};

/// A pass whose residual exceeds the best of the step by this factor discards the
/// acceleration history: the active set changed and the old differences mislead.
constexpr double kRestartGrowth = 10.0;

/// Blocks of the per-step order. Contacts are stored sorted by their bodies, so a block of
/// consecutive contacts touches a few neighbouring spheres; shuffling blocks instead of
/// single contacts lets a pass stream through memory. Beyond cache a fully random order
/// costs ≈ 370 ns per update, blocks of 256 contacts ≈ 36 ns (bench, 100 000 spheres). The
/// order stays random at every scale above a block, and a system always has at least
/// kMinBlocks blocks, so small systems (all in cache) get an almost fully random order.
constexpr std::size_t kMaxVisitBlock = 256;
constexpr std::size_t kMinBlocks = 1024;

/// order = a random permutation of blocks of consecutive contact indices.
void shuffle_blocks(std::vector<ContactIndex>& order, std::vector<ContactIndex>& blocks, Rng& rng) {
  const std::size_t n = order.size();
  const std::size_t block = std::clamp<std::size_t>(n / kMinBlocks, 1, kMaxVisitBlock);
  const std::size_t block_count = (n + block - 1) / block;
  blocks.resize(block_count);
  std::iota(blocks.begin(), blocks.end(), ContactIndex{0});
  shuffle_indices(std::span<ContactIndex>(blocks), rng);
  std::size_t o = 0;
  for (const ContactIndex b : blocks) {
    const std::size_t first = b * block;
    const std::size_t last = std::min(n, first + block);
    for (std::size_t k = first; k < last; ++k) order[o++] = static_cast<ContactIndex>(k);
  }
}

/// Replaces the actions by `mixed` and moves the velocity cache by the difference, so
/// v* stays v_free + Δt M⁻¹ Σ (contact actions) (§5.3). Modes left out of the mixing stay
/// as they are (zero). With the coloured kernel (`coloured` not null) the pairs' changes are
/// applied batch by batch, in the same order per sphere: the same bits.
void adopt(const AlignedVector<double>& mixed, MixedModes modes, Contacts& contacts,
           VelocityCache& velocities, ColouredPass* coloured) {
  with_modes(modes, [&](auto rolling, auto twisting) {
    constexpr bool kRolling = decltype(rolling)::value;
    constexpr bool kTwisting = decltype(twisting)::value;
    constexpr std::size_t kStride = MixedModes{kRolling, kTwisting}.doubles_per_action();
    const double* m = mixed.data();
    const auto take = [&](ContactAction& a) {
      ContactAction delta = take_mixed<kRolling, kTwisting>(m, a);
      m += kStride;
      return delta;
    };
    if (coloured != nullptr) {
      std::vector<ContactAction>& deltas = coloured->action_scratch;  // free during the solve
      deltas.resize(contacts.pairs.size());
      for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
        deltas[k] = take(contacts.pair_actions[k]);
      }
      apply_pair_deltas(*coloured, deltas, contacts, velocities);
    } else {
      for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
        apply_pair_action(contacts.pairs[k], take(contacts.pair_actions[k]), velocities);
      }
    }
    for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
      apply_wall_action(contacts.walls[k], take(contacts.wall_actions[k]), velocities);
    }
  });
}

/// Σ |X|² over all contacts (torques scaled by 1/r_eff), for the relative-change rule only:
/// a separate pass, so the kernel does not pay for it under the default rule. `record_of`:
/// where pair k's record is (ColouredPass::record_of; null: at k).
double sum_action_size_sq(const Contacts& contacts, const ContactIndex* record_of) {
  double sum = 0.0;
  const auto add = [&](const ContactAction& a, double inv_r_sq) {
    sum += detail::action_size_sq(a.normal_force, a.tangential_force, a.rolling_torque,
                                  a.twisting_torque, inv_r_sq);
  };
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = pair_record_at(contacts, record_of, k);
    add(contacts.pair_actions[k], detail::torque_scale_sq(p.r_eff));
  }
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    add(contacts.wall_actions[k], detail::torque_scale_sq(contacts.walls[k].radius));
  }
  return sum;
}

}  // namespace

namespace {

bool share_a_sphere(const PairProblem& p, const PairProblem& q) {
  return p.a == q.a || p.a == q.b || p.b == q.a || p.b == q.b;
}

}  // namespace

PassSums run_scalar_pass(Contacts& contacts, VelocityCache& velocities) {
  PassSums sums;
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  std::vector<SphereVelocity>& spheres = velocities.spheres;
  const std::vector<ContactIndex>& order = contacts.visit_order;
  const std::size_t n = order.size();
  std::size_t i = 0;
  while (i < n) {
    // Two consecutive pair visits without a common sphere are independent: solved side by
    // side they give exactly what one after the other gives, and the CPU overlaps their
    // dependency chains (one visit alone is a chain of ≈ 200 cycles, bound by latency).
    if (i + 1 < n && order[i] < n_pairs && order[i + 1] < n_pairs &&
        !share_a_sphere(contacts.pairs[order[i]], contacts.pairs[order[i + 1]])) {
      const ContactIndex k0 = order[i];
      const ContactIndex k1 = order[i + 1];
      const PairProblem& p0 = contacts.pairs[k0];
      const PairProblem& p1 = contacts.pairs[k1];
      ContactAction& x0 = contacts.pair_actions[k0];
      ContactAction& x1 = contacts.pair_actions[k1];
      VisitChange c0;
      VisitChange c1;
      solve_two_pairs(p0, x0, spheres[p0.a], spheres[p0.b], c0, p1, x1, spheres[p1.a],
                      spheres[p1.b], c1);
      add_visit(sums, c0, x0.normal_force, p0.cohesion);
      add_visit(sums, c1, x1.normal_force, p1.cohesion);
      i += 2;
      continue;
    }
    visit_contact(order[i], contacts, velocities, sums);
    ++i;
  }
  return sums;
}

void prepare_visit_order(Contacts& contacts, VisitOrder policy, NlgsWorkspace& work) {
  std::vector<ContactIndex>& order = contacts.visit_order;
  order.resize(contacts.size());
  std::iota(order.begin(), order.end(), ContactIndex{0});
  if (policy == VisitOrder::RandomEachStep) shuffle_blocks(order, work.blocks, work.rng);
}

namespace {

SolverStats iterate_until_done(Contacts& contacts, VelocityCache& velocities,
                               const SolverSettings& settings, double reference_force,
                               TileThreads* threads, NlgsWorkspace& work, MixedModes modes);
}  // namespace

SolverStats solve_nlgs(Contacts& contacts, VelocityCache& velocities,
                       const SolverSettings& settings, double reference_force, NlgsWorkspace& work,
                       const StepTiles* tiles) {
  if (settings.kernel != PassKernel::Coloured) {
    prepare_visit_order(contacts, settings.visit_order, work);
    return iterate_until_done(contacts, velocities, settings, reference_force, nullptr, work,
                              mixed_modes(contacts));
  }
  if (tiles != nullptr && !tiles->tiled()) tiles = nullptr;
  TileThreads* const pool = work.threads.get(solve_threads(settings));
  // before the actions go into colour order (the records stay in storage order)
  const MixedModes modes = mixed_modes(contacts);

  // the actions are stored in colour order during the passes (and the mixing); a step whose
  // phases have tiles to share runs on the threads or on this one alone, whichever was faster
  // lately: the same bits
  const bool choose = pool != nullptr && tiles != nullptr && tiles->tiles_to_share();
  const bool threaded = choose && work.thread_choice.threaded();
  TileThreads* const runner = threaded ? pool : nullptr;
  // an MPI rank fills the batches of the tiles it solves alone (tile_ranks.hpp)
  const std::vector<std::uint8_t> solved = tiles != nullptr && rank_count() > 1
                                               ? parts_of_rank(*tiles, this_rank(), rank_count())
                                               : std::vector<std::uint8_t>{};
  prepare_coloured_pass(contacts, velocities, work.coloured, kColourChunk, tiles, runner, solved);
  work.coloured.torques = modes.rolling || modes.twisting;
  order_groups(work.coloured, settings.visit_order, work.rng);
  const auto start = std::chrono::steady_clock::now();
  // the records tile by tile during the passes (tile_order.hpp): the same bits
  if (tiles != nullptr) {
    enter_tile_order(*tiles, contacts, velocities, work.coloured, work.order, runner);
  }
  // the tiles of each phase shared among the ranks of an MPI job (tile_ranks.hpp)
  work.ranks.plan(tiles, work.coloured, work.order, contacts);
  SolverStats stats =
      iterate_until_done(contacts, velocities, settings, reference_force, runner, work, modes);
  // every rank ends with every record and action
  work.ranks.share_solution(contacts, work.coloured, velocities);
  if (choose) {
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    work.thread_choice.record(
        took.count(), static_cast<double>(stats.passes) * static_cast<double>(contacts.size()));
  }
  stats.threaded = threaded;
  leave_tile_order(contacts, velocities, work.coloured, work.order, runner);
  restore_storage_order(contacts, work.coloured, runner);
  return stats;
}

namespace {

/// The accelerator's buffers kept from step to step (re-allocating them every step cost a
/// fifth of a paper-size run: page faults on fresh 200 kB vectors), its history cleared, and
/// the step's starting actions as the first iterate; a tiled step's walls part by part, as its
/// mixing keeps them (tile_solve.hpp).
void begin_acceleration(const Contacts& contacts, const SolverSettings& settings,
                        NlgsWorkspace& work, MixedModes modes, bool tiled) {
  if (work.accelerator.depth() != settings.acceleration_depth) {
    work.accelerator.set_depth(settings.acceleration_depth);
  } else {
    work.accelerator.reset();
  }
  flatten(contacts, modes, work.start, tiled ? work.coloured.mixing_walls.data() : nullptr);
  work.start_is_last_output = false;
}

/// The measured contraction of the force corrections and, for the kinematic rule, of the
/// spheres' and the piston's velocity changes.
struct ContractionWindows {
  ContractionWindow forces;
  ContractionWindow spheres_moved;
  ContractionWindow piston_moved;
};

/// The stopping gauges of `pass` from its sums and motion (physics.md §7.2): force scale,
/// residual, relative change, contraction and error estimate, and the kinematic rule's
/// errors once its window is full.
void measure_pass(int pass, const PassSums& sums, const PassMotion& motion, bool kinematic_rule,
                  const Contacts& contacts, const ContactIndex* record_of,
                  const VelocityCache& velocities, const SolverSettings& settings,
                  double reference_force, ContractionWindows& windows, SolverStats& stats) {
  const double mean_closed =
      sums.closed > 0 ? sums.sum_closed_normal / static_cast<double>(sums.closed) : 0.0;
  stats.force_scale = std::max({reference_force, mean_closed, 1e-300});
  stats.passes = pass;
  stats.residual = std::sqrt(sums.max_change_sq) / stats.force_scale;
  if (settings.stopping_rule == StoppingRule::RelativeChange) {
    const double size_sq = sum_action_size_sq(contacts, record_of);
    stats.relative_change = size_sq > 0.0 ? std::sqrt(sums.sum_change_sq / size_sq) : 0.0;
  }
  stats.contraction = windows.forces.add(pass, stats.residual);
  // min() of the two forms: residual/(1 − ρ) ≤ 999.99… × residual when ρ ≤ 0.999, so the
  // default bound of 1000 returns the first form to the last bit
  stats.error_estimate = std::min(stats.residual / (1.0 - stats.contraction),
                                  stats.residual * settings.max_error_amplification);
  if (!kinematic_rule) return;
  const auto estimate = [&](ContractionWindow& window, double change) {
    const double rho = window.add(pass, change);
    return std::min(change / (1.0 - rho), change * settings.max_error_amplification);
  };
  const double sphere_change =
      settings.kinematic_norm == KinematicNorm::Rms ? motion.rms_change : motion.largest_change;
  const double sphere_error = estimate(windows.spheres_moved, sphere_change);
  const double piston_error = estimate(windows.piston_moved, motion.piston_change);
  if (pass > kContractionWindow) {
    // relative to the motion: a packing at rest never stops on this rule (its noise would
    // let it creep), a flowing front stops once its velocities are settled to κ
    stats.kinematic_error = sphere_error / std::max(motion.rms_surface_speed, 1e-300);
    stats.piston_speed_error =
        piston_error / std::max(std::abs(velocities.piston_velocity), 1e-300);
  }
}

/// Whether the step may end after `pass`: at least min_passes, and the force rule or the
/// kinematic rule met.
bool passes_done(int pass, bool kinematic_rule, const SolverSettings& settings,
                 const SolverStats& stats) {
  const bool forces_done = settings.stopping_rule == StoppingRule::Residual
                               ? stats.error_estimate <= settings.tolerance
                               : stats.relative_change <= settings.tolerance;
  const bool kinematics_done = kinematic_rule && pass > kContractionWindow &&
                               stats.kinematic_error <= settings.kinematic_tolerance &&
                               stats.piston_speed_error <= settings.kinematic_tolerance;
  return pass >= settings.min_passes && (forces_done || kinematics_done);
}

/// One Anderson mixing of the actions after a pass; the next mixing starts from the mixed
/// actions, or from the pass's (the accelerator's last output) when none was adopted.
void mix_actions(Contacts& contacts, VelocityCache& velocities, TileThreads* threads,
                 NlgsWorkspace& work, MixedModes modes, bool coloured, bool tiled,
                 KinematicChange* kinematic) {
  // the iterate the pass started from; the mixed actions are written over work.start, which
  // the mixing reads first when x is there
  const double* const x =
      work.start_is_last_output ? work.accelerator.last_output() : work.start.data();
  bool mixed = false;
  if (tiled) {
    mixed = mix_tiled_step(x, work.start, modes, work.accelerator, contacts, velocities,
                           work.coloured, threads, kinematic, work.range_sums, &work.ranks);
  } else {
    work.accelerator.begin(work.start.size());
    flatten_range(contacts, modes, 0, contacts.size(), work.accelerator.output());
    mixed = work.accelerator.extrapolate(x, work.start.data());
    if (mixed) {
      adopt(work.start, modes, contacts, velocities, coloured ? &work.coloured : nullptr);
      if (kinematic != nullptr) work.kinematic.velocities_changed(velocities);
    }
  }
  work.start_is_last_output = !mixed;
}

SolverStats iterate_until_done(Contacts& contacts, VelocityCache& velocities,
                               const SolverSettings& settings, double reference_force,
                               TileThreads* threads, NlgsWorkspace& work, MixedModes modes) {
  std::vector<ContactIndex>& order = contacts.visit_order;
  const bool coloured = settings.kernel == PassKernel::Coloured;
  const bool accelerate = settings.acceleration_depth > 0;
  // a tiled step (tiles.hpp) runs its passes phase by phase, the kinematic rule's pass in pieces
  // of spheres and the mixing in pieces (tile_solve.hpp)
  const bool tiled = coloured && work.coloured.tiled();
  if (accelerate) begin_acceleration(contacts, settings, work, modes, tiled);
  double best_residual = std::numeric_limits<double>::infinity();

  SolverStats stats;
  if (contacts.size() == 0) {
    stats.converged = true;
    return stats;
  }
  ContractionWindows windows;
  const bool kinematic_rule = settings.kinematic_tolerance > 0.0;
  KinematicChange* const kinematic = kinematic_rule ? &work.kinematic : nullptr;
  for (int pass = 1; pass <= settings.max_passes; ++pass) {
    // a fresh order every pass, so corrections spread without a preferred direction (§7.1)
    if (settings.visit_order == VisitOrder::RandomEachPass) {
      if (coloured) {
        order_groups(work.coloured, settings.visit_order, work.rng);
      } else {
        shuffle_indices(std::span<ContactIndex>(order), work.rng);
      }
    }
    if (kinematic_rule && pass == 1) {
      // a tiled step's pieces are its tiles, their records in tile order (tile_order.hpp; no
      // sphere is in the hub), handed out row by row: ColouredPass::strip_order without the hub
      std::span<const std::uint32_t> pieces;
      std::span<const std::uint32_t> strips;
      if (tiled) {
        pieces = work.order.part_start;
        strips = work.coloured.strip_order;
        strips = strips.first(std::min(strips.size(), pieces.size() - 1));
      }
      work.kinematic.begin_step(velocities, pieces, settings.kinematic_norm == KinematicNorm::Rms,
                                &work.ranks, threads, strips);
    }
    // the estimates of the kinematic rule need a full window of passes (ρ over two passes at the
    // start of a step is optimistic), so its test and the RMS speed wait for it; the windows
    // fill from pass 1
    const bool window_full = pass > kContractionWindow;
    PassMotion motion;
    PassSums sums;
    // a tiled step's phases and the kinematic rule's pieces on the threads
    sums = coloured ? run_coloured_pass(contacts, velocities, work.coloured, threads, &work.ranks)
                    : run_scalar_pass(contacts, velocities);
    if (kinematic_rule) motion = work.kinematic.after_pass(velocities, window_full, threads);
    // the relative-change rule sums over every action (an MPI job's ranks hold their own tiles')
    if (settings.stopping_rule == StoppingRule::RelativeChange) {
      work.ranks.share_actions(contacts, work.coloured);
    }
    measure_pass(pass, sums, motion, kinematic_rule, contacts,
                 coloured ? work.coloured.record_of() : nullptr, velocities, settings,
                 reference_force, windows, stats);
    if (passes_done(pass, kinematic_rule, settings, stats)) {
      stats.converged = true;
      break;
    }
    if (settings.stop_request != nullptr && *settings.stop_request && (*settings.stop_request)()) {
      stats.stopped = true;  // on this pass's output, before any mixing
      break;
    }

    // Mixing comes after the test and never after the last pass: a mixed iterate is an
    // affine combination that need not obey the contact laws (R_n < −F_c, forces outside
    // the friction cone, forces on open contacts), so a step must end on a pass's output.
    if (accelerate && pass % settings.acceleration_interval == 0 && pass < settings.max_passes) {
      if (stats.residual > kRestartGrowth * best_residual) work.accelerator.reset();
      best_residual = std::min(best_residual, stats.residual);
      mix_actions(contacts, velocities, threads, work, modes, coloured, tiled, kinematic);
    }
  }
  return stats;
}

}  // namespace

}  // namespace cdpowder
