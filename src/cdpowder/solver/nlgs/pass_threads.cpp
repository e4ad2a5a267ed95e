// sweep_threads.cpp — the pool's command word, its spinning and its parking.
#include "cdpowder/solver/nlgs/pass_threads.hpp"

#include <chrono>

namespace cdpowder {

namespace {

enum class Command : std::uint32_t { Run = 0, Park = 1, Stop = 2 };
constexpr std::uint32_t kCommandBits = 2;

/// The command word: a sequence number (so that a repeated command is a new value) and a kind.
std::uint32_t command_word(std::uint32_t sequence, Command kind) {
  return (sequence << kCommandBits) | static_cast<std::uint32_t>(kind);
}

/// Spins between two yields of the time slice: ≈ 5–20 µs of spinning, so a waiting thread
/// on an idle machine rarely makes a system call, and on an oversubscribed one lets the
/// thread it waits for run.
constexpr int kSpinsBeforeYield = 256;

/// How long a parked worker keeps spinning before it sleeps. The run loop's work between two
/// steps' solves (detection, building the local problems, integration, diagnostics) takes
/// 100–250 µs at paper size; a worker still spinning when the next step starts takes its
/// first piece at once, where a sleeping one is woken by a system call and scheduled tens of
/// microseconds later, after the caller has done the first passes alone
/// (docs/lab/2026-11-26-two-slabs.md). Past it the worker sleeps: a run that stops stepping
/// does not burn a core.
constexpr std::chrono::microseconds kSpinAfterPark{1000};

/// Checks the clock every this many spins (a clock read costs ≈ 20 ns, a pause ≈ 10–40 ns).
constexpr int kSpinsPerClockRead = 64;

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();  // spin-wait hint: saves power, frees the core's other hyperthread
#endif
}

}  // namespace

void spin_until_true(bool (*done)(const void*), const void* context) {
  int spins = 0;
  while (!done(context)) {
    pause();
    if (++spins == kSpinsBeforeYield) {
      spins = 0;
      std::this_thread::yield();
    }
  }
}

PassThreads::PassThreads(int threads) {
  const int workers = threads > 1 ? threads - 1 : 0;
  workers_.reserve(static_cast<std::size_t>(workers));
  for (int t = 1; t <= workers; ++t) workers_.emplace_back([this, t] { work(t); });
}

PassThreads::~PassThreads() {
  command_.store(command_word(++sequence_, Command::Stop), std::memory_order_release);
  command_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void PassThreads::start(Task task, void* context) {
  if (workers_.empty()) return;
  task_.store(task, std::memory_order_relaxed);
  context_.store(context, std::memory_order_relaxed);
  command_.store(command_word(++sequence_, Command::Run), std::memory_order_release);
  // only a parked worker sleeps; a spinning one sees the store without a system call
  if (parked_) command_.notify_all();
  parked_ = false;
}

void PassThreads::park() {
  if (parked_ || workers_.empty()) return;
  command_.store(command_word(++sequence_, Command::Park), std::memory_order_release);
  parked_ = true;
}

void PassThreads::work(int thread) {
  using Clock = std::chrono::steady_clock;
  std::uint32_t seen = 0;
  bool parked = true;
  bool asleep = true;  // parked and past kSpinAfterPark: sleeps on the futex
  Clock::time_point parked_at{};
  for (;;) {
    const std::uint32_t command = command_.load(std::memory_order_acquire);
    if (command == seen) {
      if (asleep) {
        command_.wait(seen, std::memory_order_acquire);  // sleeps until the value changes
      } else if (parked) {
        // spin a while after a park: the next step most likely starts soon
        int spins = 0;
        spin_until([&] {
          if (command_.load(std::memory_order_relaxed) != seen) return true;
          if (++spins % kSpinsPerClockRead != 0) return false;
          asleep = Clock::now() - parked_at > kSpinAfterPark;
          return asleep;
        });
      } else {
        spin_until([&] { return command_.load(std::memory_order_relaxed) != seen; });
      }
      continue;
    }
    seen = command;
    switch (static_cast<Command>(command & ((1U << kCommandBits) - 1))) {
      case Command::Run:
        parked = asleep = false;
        task_.load(std::memory_order_relaxed)(context_.load(std::memory_order_relaxed), thread);
        break;
      case Command::Park:
        parked = true;
        parked_at = Clock::now();
        break;
      case Command::Stop:
        return;
    }
  }
}

}  // namespace cdpowder
