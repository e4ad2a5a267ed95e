// sweep_threads.hpp — a small persistent pool of threads for the sweeps of the coloured kernel
// (solver.threads, coloured_threads.hpp). A sweep at paper size is ≈ 85 µs over 10–20 colours,
// one barrier per colour, so the barrier must cost far less than a microsecond: the threads
// spin on atomics (no mutex, no condition variable) while a step's sweeps run, and sleep
// (std::atomic::wait, a futex) between steps so an idle run does not burn a core.
// Chosen over OpenMP: the pool is created once per workspace and its spinning and parking are
// under our control (OpenMP's spin-wait policy is an environment setting of the runtime).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

namespace cdpowder {

class SweepThreads {
 public:
  /// A task run on every thread: task(context, t) for t = 0 (the caller) … size() − 1.
  using Task = void (*)(void* context, int thread);

  /// Starts threads − 1 workers (threads ≥ 1), parked until the first run().
  explicit SweepThreads(int threads);
  ~SweepThreads();
  SweepThreads(const SweepThreads&) = delete;
  SweepThreads& operator=(const SweepThreads&) = delete;

  [[nodiscard]] int size() const { return static_cast<int>(slots_.size()); }

  /// Runs task on all threads and returns once every thread has finished it. After run() the
  /// workers spin, waiting for the next run(), until park().
  void run(Task task, void* context);

  /// Lets the workers sleep until the next run() (between steps).
  void park();

  /// Inside a task: returns once every thread has reached its same barrier (every thread must
  /// pass the same number of barriers in a task). Memory written before the barrier by any
  /// thread is visible after it to all.
  void barrier(int thread);

 private:
  /// One cache line per thread: how many barriers the thread has reached.
  struct alignas(64) Slot {
    std::atomic<std::uint64_t> arrived{0};
  };

  void work(int thread);
  void arrive(int thread);
  void wait_for_all(int thread);

  std::vector<Slot> slots_;
  /// sequence << 2 | command kind: a new value starts a task, parks or stops the workers
  alignas(64) std::atomic<std::uint32_t> command_{0};
  std::uint32_t sequence_ = 0;
  bool parked_ = true;
  Task task_ = nullptr;
  void* context_ = nullptr;
  std::vector<std::thread> workers_;
};

/// A workspace's pool, started at the first step that asks for more than one thread and kept
/// for the run. The pool is scratch, not state: a copy of a workspace (the run loop solves a
/// copy at rest) starts its own pool when it needs one, and an assignment keeps the target's.
class SweepThreadsSlot {
 public:
  SweepThreadsSlot() = default;
  ~SweepThreadsSlot() = default;

  SweepThreadsSlot(const SweepThreadsSlot& /*other*/) {}

  SweepThreadsSlot& operator=(const SweepThreadsSlot& /*other*/) { return *this; }

  SweepThreadsSlot(SweepThreadsSlot&&) noexcept = default;
  SweepThreadsSlot& operator=(SweepThreadsSlot&&) noexcept = default;

  /// The pool of `threads` threads (started or resized here); nullptr for one thread.
  SweepThreads* get(int threads);

 private:
  std::unique_ptr<SweepThreads> pool_;
};

}  // namespace cdpowder
