// pass_threads.hpp — a small persistent pool of threads for the solve of a tiled step
// (solver.threads, tile_threads.hpp). A pass at paper size is ≈ 30 µs and hands work to the
// other threads once per phase, so a hand-over must cost a few percent of that at most: the
// threads spin on atomics (no mutex, no condition variable) while a step's passes run, go on
// spinning for a millisecond after a step (the next one usually starts within a quarter of
// that), and then sleep (std::atomic::wait, a futex), so a run that stops stepping does not
// burn a core.
// Chosen over OpenMP: the pool is created once per workspace, its spinning and parking are
// under our control (OpenMP's spin-wait policy is an environment setting of the runtime), and
// the caller never waits for a worker that has no work (an OpenMP parallel region ends with a
// barrier of all threads: on a loaded machine one descheduled worker stalls every pass).
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace cdpowder {

/// Spins until done() is true, yielding the time slice now and then: a thread that spins
/// while the machine is oversubscribed holds back the thread it waits for.
void spin_until_true(bool (*done)(const void*), const void* context);

template <typename Done>
void spin_until(Done done) {
  if (done()) return;
  spin_until_true([](const void* d) { return (*static_cast<const Done*>(d))(); }, &done);
}

class PassThreads {
 public:
  /// A task run on the workers: task(context, t) for t = 1 … size() − 1.
  using Task = void (*)(void* context, int thread);

  /// Starts threads − 1 workers (threads ≥ 1), parked until the first start().
  explicit PassThreads(int threads);
  ~PassThreads();
  PassThreads(const PassThreads&) = delete;
  PassThreads(PassThreads&&) = delete;
  PassThreads& operator=(const PassThreads&) = delete;
  PassThreads& operator=(PassThreads&&) = delete;

  [[nodiscard]] int size() const { return static_cast<int>(workers_.size()) + 1; }

  /// Lets every worker run task(context, t) once, and returns at once: the caller works
  /// along and learns from the task's own shared state when the work is done, so it never
  /// waits for a worker that is not running. A late worker (descheduled) may enter a task
  /// after its work is done, or a later task: a task must claim work before touching anything,
  /// and `context` must outlive the pool. After start() the workers spin until park().
  void start(Task task, void* context);

  /// Lets the workers sleep until the next start() (between steps): they spin for a
  /// millisecond first, so a start() soon after finds them awake.
  void park();

  /// Whether the workers were parked (park() since the last start()): they spin for a
  /// millisecond before they sleep.
  [[nodiscard]] bool parked() const { return parked_; }

 private:
  void work(int thread);

  /// sequence << 2 | command kind: a new value starts a task, parks or stops the workers
  alignas(64) std::atomic<std::uint32_t> command_{0};
  std::atomic<Task> task_{nullptr};
  std::atomic<void*> context_{nullptr};
  std::uint32_t sequence_ = 0;
  bool parked_ = true;
  std::vector<std::thread> workers_;
};

}  // namespace cdpowder
