// sweep_threads.cpp — the pool's command word, its spin barrier and its parking.
#include "cdpowder/solver/sweep_threads.hpp"

#include <cstddef>

namespace cdpowder {

namespace {

enum class Command : std::uint32_t { Run = 0, Park = 1, Stop = 2 };

constexpr std::uint32_t kCommandBits = 2;

/// The command word: a sequence number (so that a repeated command is a new value) and a kind.
std::uint32_t command_word(std::uint32_t sequence, Command kind) {
  return (sequence << kCommandBits) | static_cast<std::uint32_t>(kind);
}

/// Spins between two yields of the time slice. A worker that spins while the machine is
/// oversubscribed (more runnable threads than cores) holds back the thread it waits for;
/// yielding now and then bounds that, at the price of a system call after ≈ 10 µs of waiting.
constexpr int kSpinsBeforeYield = 256;

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();  // spin-wait hint: saves power, frees the core's other hyperthread
#endif
}

/// Spins until done() is true.
template <typename Done>
void spin_until(Done done) {
  int spins = 0;
  while (!done()) {
    pause();
    if (++spins == kSpinsBeforeYield) {
      spins = 0;
      std::this_thread::yield();
    }
  }
}

}  // namespace

SweepThreads::SweepThreads(int threads)
    : slots_(static_cast<std::size_t>(threads < 1 ? 1 : threads)) {
  workers_.reserve(slots_.size() - 1);
  for (int t = 1; t < size(); ++t) workers_.emplace_back([this, t] { work(t); });
}

SweepThreads::~SweepThreads() {
  command_.store(command_word(++sequence_, Command::Stop), std::memory_order_release);
  command_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void SweepThreads::run(Task task, void* context) {
  task_ = task;
  context_ = context;
  if (!workers_.empty()) {
    command_.store(command_word(++sequence_, Command::Run), std::memory_order_release);
    // only a parked worker sleeps; a spinning one sees the store without a system call
    if (parked_) command_.notify_all();
    parked_ = false;
  }
  task(context, 0);
  // the workers arrive without waiting when done; the caller waits for them
  barrier(0);
}

void SweepThreads::park() {
  if (parked_ || workers_.empty()) return;
  command_.store(command_word(++sequence_, Command::Park), std::memory_order_release);
  parked_ = true;
}

void SweepThreads::arrive(int thread) {
  Slot& slot = slots_[static_cast<std::size_t>(thread)];
  slot.arrived.store(slot.arrived.load(std::memory_order_relaxed) + 1, std::memory_order_release);
}

void SweepThreads::wait_for_all(int thread) {
  const std::uint64_t phase =
      slots_[static_cast<std::size_t>(thread)].arrived.load(std::memory_order_relaxed);
  for (const Slot& other : slots_) {
    spin_until([&] { return other.arrived.load(std::memory_order_acquire) >= phase; });
  }
}

void SweepThreads::barrier(int thread) {
  arrive(thread);
  wait_for_all(thread);
}

void SweepThreads::work(int thread) {
  std::uint32_t seen = 0;
  bool parked = true;
  for (;;) {
    const std::uint32_t command = command_.load(std::memory_order_acquire);
    if (command == seen) {
      if (parked) {
        command_.wait(seen, std::memory_order_acquire);  // sleeps until the value changes
      } else {
        spin_until([&] { return command_.load(std::memory_order_relaxed) != seen; });
      }
      continue;
    }
    seen = command;
    switch (static_cast<Command>(command & ((1U << kCommandBits) - 1))) {
      case Command::Run:
        parked = false;
        task_(context_, thread);
        arrive(thread);
        break;
      case Command::Park:
        parked = true;
        break;
      case Command::Stop:
        return;
    }
  }
}

SweepThreads* SweepThreadsSlot::get(int threads) {
  if (threads <= 1) {
    pool_.reset();
  } else if (!pool_ || pool_->size() != threads) {
    pool_.reset();  // the old workers stop before the new ones start
    pool_ = std::make_unique<SweepThreads>(threads);
  }
  return pool_.get();
}

}  // namespace cdpowder
