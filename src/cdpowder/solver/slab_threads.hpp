// slab_threads.hpp — the two slabs of a step (slabs.hpp) on two threads (solver.threads = 2).
// A sweep hands out its work in a few pieces that touch no common memory they write: the
// contacts inside each slab, the two halves of the kinematic rule's pass over the spheres, the
// two halves of the mixing's passes. Any thread may take any piece (the caller as well as the
// worker, claimed from one shared counter), so the caller never waits for a worker that is not
// running: on a loaded machine a descheduled worker's pieces are taken by the caller. The
// pieces are fixed by the state, not by the thread count, and every sum over pieces is added
// in piece order by the caller, so the results are the same bits on one thread or two.
#pragma once

#include "cdpowder/solver/sweep_threads.hpp"

#include <atomic>
#include <cstdint>
#include <memory>

namespace cdpowder {

class SlabThreads {
 public:
  /// Starts threads − 1 workers (threads ≥ 1).
  explicit SlabThreads(int threads) : pool_(threads) {}

  [[nodiscard]] int size() const { return pool_.size(); }

  /// Runs task(piece) for piece = 0 … pieces − 1, each exactly once, on whichever thread
  /// claims it first, and returns when all are done. Pieces must not write common memory.
  template <typename Task>
  void run(std::uint32_t pieces, const Task& task) {
    run_pieces(
        pieces, [](const void* t, std::uint32_t piece) { (*static_cast<const Task*>(t))(piece); },
        &task);
  }

  /// Lets the workers sleep until the next run (between steps).
  void park() { pool_.park(); }

 private:
  using PieceTask = void (*)(const void* context, std::uint32_t piece);

  void run_pieces(std::uint32_t pieces, PieceTask task, const void* context);
  static void work(void* self, int thread);
  bool claim(std::uint32_t& piece);
  void solve_claimed();

  /// id (32 bits) | pieces (16 bits) | next piece (16 bits): a claim is one compare-exchange,
  /// and a late worker's claim on an earlier run fails on the id
  alignas(64) std::atomic<std::uint64_t> claim_{0};
  alignas(64) std::atomic<std::uint32_t> done_{0};  ///< pieces done in this run
  alignas(64) std::uint32_t run_id_ = 0;
  // the run's task, written before claim_ publishes it and read by a thread after a claim
  PieceTask task_ = nullptr;
  const void* context_ = nullptr;
  /// last member: its workers are stopped before the state above is destroyed
  SweepThreads pool_;
};

/// Runs task(0) … task(pieces − 1) on `threads`, or one after the other on the caller when
/// `threads` is null.
template <typename Task>
void run_pieces(SlabThreads* threads, std::uint32_t pieces, Task&& task) {
  if (threads != nullptr) {
    threads->run(pieces, task);
    return;
  }
  for (std::uint32_t p = 0; p < pieces; ++p) task(p);
}

/// A workspace's SlabThreads, started at the first step that asks for more than one thread
/// and kept for the run. Scratch, not state: a copy of a workspace (the run loop solves a copy
/// at rest) starts its own threads when it needs them, and an assignment keeps the target's.
class SlabThreadsSlot {
 public:
  SlabThreadsSlot() = default;
  ~SlabThreadsSlot() = default;

  SlabThreadsSlot(const SlabThreadsSlot& /*other*/) {}

  SlabThreadsSlot& operator=(const SlabThreadsSlot& /*other*/) { return *this; }

  SlabThreadsSlot(SlabThreadsSlot&&) noexcept = default;
  SlabThreadsSlot& operator=(SlabThreadsSlot&&) noexcept = default;

  /// The threads of `threads` (started or resized here); nullptr for one thread.
  SlabThreads* get(int threads);

 private:
  std::unique_ptr<SlabThreads> threads_;
};

}  // namespace cdpowder
