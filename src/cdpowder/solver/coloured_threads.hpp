// coloured_threads.hpp — the coloured sweep on several threads (solver.threads > 1). Within a
// colour no two contacts share a sphere, so a colour's batches are cut into pieces (one per
// thread) that any thread may solve; a piece of a colour starts once every piece of the
// colours before it is done (one shared counter: the barrier between colours), and the
// sequential group (overflow pairs, wall and piston contacts) is one piece. The threads claim
// the pieces in visiting order from a shared counter, so the caller never waits for a worker
// that is not running (a descheduled worker's pieces are taken by the others). The visits
// are kept per batch and added to the sweep sums afterwards in the visiting order, so a sweep
// gives the bits of run_coloured_sweep for any thread count.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/solver/coloured_sweep.hpp"
#include "cdpowder/solver/sweep_sums.hpp"
#include "cdpowder/solver/sweep_threads.hpp"
#include "cdpowder/solver/velocity_cache.hpp"

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace cdpowder {

/// A visit of the sequential group, kept for the sums (closed_normal as in sweep_sums.hpp).
struct KeptVisit {
  double change_sq = 0.0;
  double closed_normal = -1.0;
};

/// The workers and the shared state of coloured sweeps on several threads, kept for a run.
class ColouredThreads {
 public:
  /// With `adaptive`, each sweep runs on the threads or on the caller alone, whichever was
  /// faster lately (see sweep()); else always on the threads (tests, benchmarks).
  explicit ColouredThreads(int threads, bool adaptive = true)
      : adaptive_(adaptive), pool_(threads) {}

  [[nodiscard]] int size() const { return pool_.size(); }

  /// One sweep over the groups in sweep.group_order: the same bits (state and sums) as
  /// run_coloured_sweep, on the threads or not. On a loaded machine a sweep on threads can be
  /// slower than on one (a worker descheduled while it holds a piece stalls the next colour
  /// for a time slice); since the bits do not depend on it, the adaptive mode times both and
  /// runs the faster, trying the other one every kProbeInterval sweeps.
  SweepSums sweep(Contacts& contacts, VelocityCache& velocities, const ColouredSweep& sweep);

  /// Lets the workers sleep until the next sweep (between steps).
  void park() { pool_.park(); }

 private:
  /// A piece of the sweep: batches [first, last) of one colour, or the sequential group.
  struct Piece {
    std::uint32_t first = 0;
    std::uint32_t last = 0;
    bool sequential = false;
    std::uint32_t wait_for = 0;  ///< pieces of the earlier groups, done before this one starts
  };

  SweepSums sweep_on_threads(Contacts& contacts, VelocityCache& velocities,
                             const ColouredSweep& sweep);
  static void work(void* self, int thread);
  bool claim(std::uint32_t& piece);
  void solve_claimed();
  [[nodiscard]] SweepSums add_in_visiting_order() const;

  /// id (24 bits) | pieces (20 bits) | next piece (20 bits): a claim is one compare-exchange,
  /// and a late worker's claim on an earlier sweep fails on the id
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  alignas(64) std::atomic<std::uint32_t> done_{0};  ///< pieces done in this sweep
  alignas(64) std::uint32_t sweep_id_ = 0;
  bool adaptive_;
  std::uint64_t sweeps_ = 0;
  double threaded_ns_ = 0.0;  ///< recent ns per contact on the threads (0: not measured)
  double solo_ns_ = 0.0;      ///< recent ns per contact on the caller alone (0: not measured)
  // the sweep, written before claim_ publishes it and read by a thread only after a claim
  Contacts* contacts_ = nullptr;
  VelocityCache* velocities_ = nullptr;
  const ColouredSweep* sweep_ = nullptr;
  std::vector<Piece> pieces_;
  std::vector<BatchVisits> batch_visits_;  ///< batch i's visits
  std::vector<KeptVisit> sequential_visits_;
  /// last member: its workers are stopped before the state above is destroyed
  SweepThreads pool_;
};

/// A workspace's ColouredThreads, started at the first step that asks for more than one thread
/// and kept for the run. Scratch, not state: a copy of a workspace (the run loop solves a copy
/// at rest) starts its own threads when it needs them, and an assignment keeps the target's.
class ColouredThreadsSlot {
 public:
  ColouredThreadsSlot() = default;
  ~ColouredThreadsSlot() = default;

  ColouredThreadsSlot(const ColouredThreadsSlot& /*other*/) {}

  ColouredThreadsSlot& operator=(const ColouredThreadsSlot& /*other*/) { return *this; }

  ColouredThreadsSlot(ColouredThreadsSlot&&) noexcept = default;
  ColouredThreadsSlot& operator=(ColouredThreadsSlot&&) noexcept = default;

  /// The threads of `threads` (started or resized here); nullptr for one thread.
  ColouredThreads* get(int threads);

 private:
  std::unique_ptr<ColouredThreads> threads_;
};

}  // namespace cdpowder
