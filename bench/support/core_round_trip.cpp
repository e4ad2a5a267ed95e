// core_round_trip.cpp — a cache line bounced between two pinned threads.
#include "support/core_round_trip.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <thread>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace cdpowder::bench {

namespace {

/// Pins the calling thread to `cpu`; false where it cannot.
bool pin_to(int cpu) {
#if defined(__linux__)
  if (cpu < 0 || cpu >= CPU_SETSIZE) return false;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0;
#else
  (void)cpu;
  return false;
#endif
}

/// Round trips per batch: ≈ 20–100 ms of bouncing, long enough to average a batch over the
/// scheduler's ticks, short enough to sit beside a benchmark.
constexpr std::uint32_t kRoundTrips = 100'000;
constexpr std::uint32_t kBatches = 5;
/// the answering thread's last value: 2 per round trip
constexpr std::uint32_t kLastValue = 2 * kRoundTrips * kBatches;

/// The calling thread's CPUs, put back when it goes out of scope: the caller measures and then
/// goes on with its own work, on whichever CPU the scheduler gives it.
class KeepAffinity {
 public:
#if defined(__linux__)
  KeepAffinity() {
    saved_ = pthread_getaffinity_np(pthread_self(), sizeof(set_), &set_) == 0;
  }

  ~KeepAffinity() {
    if (saved_) pthread_setaffinity_np(pthread_self(), sizeof(set_), &set_);
  }
#endif
  KeepAffinity(const KeepAffinity&) = delete;
  KeepAffinity& operator=(const KeepAffinity&) = delete;
  KeepAffinity(KeepAffinity&&) = delete;
  KeepAffinity& operator=(KeepAffinity&&) = delete;

 private:
#if defined(__linux__)
  cpu_set_t set_{};
  bool saved_ = false;
#endif
};

}  // namespace

double core_round_trip_ns(int first, int second) {
  const KeepAffinity keep;
  // the caller first: once it is pinned only the answering thread can fail, before it answers
  if (!pin_to(first)) return std::numeric_limits<double>::quiet_NaN();
  // the line both threads write: odd values are the caller's, even ones the answers
  alignas(64) std::atomic<std::uint32_t> line{0};
  std::atomic<int> pinned{0};  // 1 once the answering thread is pinned, −1 if it cannot be
  std::thread answering([&] {
    if (!pin_to(second)) {
      pinned.store(-1);
      return;
    }
    pinned.store(1);
    for (std::uint32_t value = 1; value < kLastValue; value += 2) {
      while (line.load(std::memory_order_acquire) != value) {
      }
      line.store(value + 1, std::memory_order_release);
    }
  });
  while (pinned.load() == 0) std::this_thread::yield();
  if (pinned.load() < 0) {
    answering.join();
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::array<double, kBatches> batch_ns{};
  std::uint32_t value = 1;
  for (double& ns : batch_ns) {
    const auto start = std::chrono::steady_clock::now();
    for (std::uint32_t k = 0; k < kRoundTrips; ++k, value += 2) {
      line.store(value, std::memory_order_release);
      while (line.load(std::memory_order_acquire) != value + 1) {
      }
    }
    const std::chrono::duration<double, std::nano> took = std::chrono::steady_clock::now() - start;
    ns = took.count() / kRoundTrips;
  }
  answering.join();
  std::sort(batch_ns.begin(), batch_ns.end());
  return batch_ns[kBatches / 2];
}

}  // namespace cdpowder::bench
