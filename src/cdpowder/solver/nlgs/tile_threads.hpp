// tile_threads.hpp — the tiles of a step (tiles.hpp) on threads (solver.threads), and the
// PieceRunner (core/pieces.hpp) of the stages around the solve: the halves of the next step's
// detection and build, and of the commit's measures.
// The threads are OpenMP's (the compiler's runtime): a run of pieces is one parallel region.
// Its waiting and pinning are the runtime's standard environment (OMP_WAIT_POLICY,
// OMP_PROC_BIND, OMP_PLACES; docs/performance.md), not settings of ours.
// A pass hands out its work in pieces that touch no common memory they write: the tiles of a
// phase, the tiles' parts of the kinematic rule's pass over the spheres and of the mixing. Any
// thread may take any piece, so a thread of the team that starts late finds its pieces taken
// by the others. The pieces are fixed by the state, not by the thread count, and every sum over
// pieces is added in piece order by the caller, so the results are the same bits on any number
// of threads.
#pragma once

#include "cdpowder/core/pieces.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace cdpowder {

class TileThreads final : public PieceRunner {
 public:
  /// A team of `threads` (≥ 1), the caller among them.
  explicit TileThreads(int threads)
      : threads_(std::max(threads, 1)), ranges_(static_cast<std::size_t>(threads_)) {}

  [[nodiscard]] int size() const { return threads_; }

  /// Runs task(context, piece) for piece = 0 … pieces − 1, each exactly once, and returns when
  /// all are done. Thread k of the team (the caller is 0) has the pieces [k P/T, (k + 1) P/T)
  /// of its own, so a tile (and its data in that core's cache) goes to the same thread in every
  /// pass; a thread done with its own takes the others' that nobody has begun. A team smaller
  /// than asked for (OMP_THREAD_LIMIT, OMP_DYNAMIC) still runs every piece.
  void run_pieces(std::uint32_t pieces, Task task, const void* context) override;

 private:
  void solve_claimed(int thread);

  /// A thread's pieces: the next to claim (one fetch-add) and the end, on a cache line of its
  /// own. Set before the parallel region, which orders them before every claim.
  struct alignas(64) Range {
    std::atomic<std::uint32_t> next{0};
    std::uint32_t end = 0;
  };

  int threads_;
  std::vector<Range> ranges_;  ///< one a thread
  // the run's task, set before the parallel region
  Task task_ = nullptr;
  const void* context_ = nullptr;
};

/// Whether a step's solve runs on the threads or on the caller alone. The bits are the same
/// either way (the tiles do not depend on it), so the choice is made on time alone: on a
/// shared machine two threads are not always faster. Runs of the paper example measured in one
/// session (docs/lab/2026-11-26-two-slabs.md) took 1.2–1.4× less time on two threads in some
/// minutes and 1.3× more in others, when the second core was not free for this process.
///
/// The steps go in blocks of kBlockSteps, each block one way: the kept way, and now and then a
/// block that tries the other (the first try is the second block). A try comes after kTryEvery
/// blocks, after twice as many (up to kMaxTryEvery) each time the way tried lost by more than
/// kClearLoss (on a machine whose cores talk slowly two threads lose 2.5× per step,
/// docs/lab/2026-11-28-a-faster-machine.md: trying them every 32nd block cost a run up to
/// 6–7 %), and at once when a block of the kept way took longer per contact update than the
/// other way's last block. A try is judged against the kept way's block just before it, and
/// the kept way changes only when two tries in a row win, with one block of the kept way
/// between them: one slow block (a hiccup of the machine, a step of many passes) kept a run of
/// 16 240 spheres on one thread for 32 blocks (docs/lab/2026-12-01-serial-stages-in-pieces.md).
/// A try that wins, or loses by less than kClearLoss, brings the interval back to kTryEvery.
/// Blocks, not single steps: one step's time is too noisy to choose by (steps differ in their
/// passes, and a step is ≈ 0.5–1.5 ms, the scale of the machine's hiccups).
class ThreadChoice {
 public:
  static constexpr std::uint64_t kBlockSteps = 16;
  static constexpr std::uint64_t kTryEvery = 32;
  /// ≈ 2–4 s of a paper-size run: a machine that turns fast is still seen within seconds
  static constexpr std::uint64_t kMaxTryEvery = 128;
  static constexpr double kClearLoss = 1.25;

  /// Whether this step should run on the threads.
  [[nodiscard]] bool threaded() const { return threaded_; }

  /// Every cut step on the threads from now on, whatever their times: for measurements of the
  /// threads alone (`fixture_steps --always-threaded`), which the choice would otherwise mix
  /// with blocks on one thread. A choice made where CDPOWDER_ALWAYS_THREADED=1 is set starts
  /// so (the same-bits tests, whose threads lose to one thread on two cores).
  ThreadChoice() {
    if (always_threaded_from_environment()) always_threaded();
  }

  void always_threaded() {
    always_ = true;
    threaded_ = true;
  }

  /// Blocks between two tries of the other way at present (kTryEvery … kMaxTryEvery).
  [[nodiscard]] std::uint64_t try_every() const { return try_every_; }

  /// The time this step took [s] for its contact updates (passes × contacts); at the end of a
  /// block, chooses the way of the next.
  void record(double seconds, double updates);

 private:
  /// Whether `way`'s last block (0 alone, 1 the threads) took less time per update than the
  /// other way's; the threads win a tie, as the way of the first block.
  [[nodiscard]] bool faster(std::size_t way) const {
    return way == 1 ? per_update_[1] <= per_update_[0] : per_update_[0] < per_update_[1];
  }

  /// Whether CDPOWDER_ALWAYS_THREADED is "1" (read once).
  static bool always_threaded_from_environment();

  /// After a block that tried the other way: keep the way, or take the tried one.
  void judge_try(std::size_t tried);

  bool threaded_ = true;                ///< the way of the current block
  bool always_ = false;                 ///< always_threaded()
  bool trying_ = false;                 ///< the current block tries the other way
  bool confirming_ = false;             ///< the last try won: the next, after one block, decides
  std::array<double, 2> per_update_{};  ///< [alone, threads] s per update of its last block
  double seconds_ = 0.0;                ///< of the current block
  double updates_ = 0.0;
  std::uint64_t steps_ = 0;
  std::uint64_t since_try_ = 0;  ///< blocks since the last try began, the try's own included
  std::uint64_t try_every_ = kTryEvery;
};

/// A workspace's TileThreads, made at the first step that asks for more than one thread and
/// kept for the run. Scratch, not state: a copy of a workspace (the run loop solves a copy at
/// rest) makes its own when it needs one, and an assignment keeps the target's.
class TileThreadsSlot {
 public:
  TileThreadsSlot() = default;
  ~TileThreadsSlot() = default;

  TileThreadsSlot(const TileThreadsSlot& /*other*/) {}

  // keeps the target's team, so a self-assignment changes nothing either
  // NOLINTNEXTLINE(bugprone-unhandled-self-assignment)
  TileThreadsSlot& operator=(const TileThreadsSlot& /*other*/) { return *this; }

  TileThreadsSlot(TileThreadsSlot&&) noexcept = default;
  TileThreadsSlot& operator=(TileThreadsSlot&&) noexcept = default;

  /// The team of `threads` (made or resized here); nullptr for one thread.
  TileThreads* get(int threads);

 private:
  std::unique_ptr<TileThreads> threads_;
};

}  // namespace cdpowder
