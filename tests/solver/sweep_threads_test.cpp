// The pool of solver.threads (sweep_threads.hpp): its barrier separates the phases of a task,
// on 1–3 threads, across runs and parking.
#include "cdpowder/solver/sweep_threads.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace cdpowder::testing {
namespace {

/// Phases of a task: every thread writes its slot, then all read all slots.
struct PhaseCheck {
  SweepThreads* threads = nullptr;
  int phases = 0;
  std::vector<int> seen;  // one slot per thread
  std::atomic<int> wrong{0};
  std::atomic<int> ran{0};
};

void check_phases(void* context, int t) {
  auto& check = *static_cast<PhaseCheck*>(context);
  check.ran.fetch_add(1);
  for (int p = 1; p <= check.phases; ++p) {
    check.seen[static_cast<std::size_t>(t)] = p;
    check.threads->barrier(t);
    for (const int s : check.seen) {
      if (s != p) check.wrong.fetch_add(1);
    }
    check.threads->barrier(t);
  }
}

TEST(SweepThreads, TheBarrierSeparatesPhasesAcrossRunsAndParking) {
  for (const int n : {1, 2, 3}) {
    SweepThreads threads(n);
    ASSERT_EQ(threads.size(), n);
    PhaseCheck check;
    check.threads = &threads;
    check.phases = 500;
    check.seen.assign(static_cast<std::size_t>(n), 0);
    for (int run = 0; run < 6; ++run) {
      threads.run(check_phases, &check);
      if (run % 2 == 1) threads.park();  // a worker woken from its sleep joins the next run
    }
    EXPECT_EQ(check.wrong.load(), 0) << n << " threads";
    EXPECT_EQ(check.ran.load(), 6 * n);
  }
}

}  // namespace
}  // namespace cdpowder::testing
