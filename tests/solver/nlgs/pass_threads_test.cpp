// The pool of solver.threads (sweep_threads.hpp): start() runs the task once on every worker
// without waiting for them, across parking and waking, on 1–3 threads.
#include "cdpowder/solver/nlgs/pass_threads.hpp"

#include <gtest/gtest.h>

#include <atomic>

namespace cdpowder::testing {
namespace {

struct Count {
  std::atomic<int> ran{0};
  std::atomic<int> threads_seen{0};  // a bit per thread index
};

void count_run(void* context, int t) {
  auto& count = *static_cast<Count*>(context);
  count.threads_seen.fetch_or(1 << t);
  count.ran.fetch_add(1);
}

TEST(PassThreads, StartRunsTheTaskOnceOnEveryWorkerAcrossParking) {
  for (const int n : {1, 2, 3}) {
    Count count;  // outlives the pool, as start() requires
    {
      PassThreads threads(n);
      ASSERT_EQ(threads.size(), n);
      for (int run = 1; run <= 6; ++run) {
        threads.start(count_run, &count);
        // start() does not wait: the caller learns from the task's own state
        spin_until([&] { return count.ran.load() == run * (n - 1); });
        if (run % 2 == 0) threads.park();  // a worker woken from its sleep joins the next run
      }
    }
    EXPECT_EQ(count.ran.load(), 6 * (n - 1));
    EXPECT_EQ(count.threads_seen.load(), (1 << n) - 2) << "workers 1 .. n-1, not the caller";
  }
}

}  // namespace
}  // namespace cdpowder::testing
