// The CPU budget (core/cpu_budget.hpp): a run never asks for more threads than its
// affinity mask, its quota and CDPOWDER_MAX_THREADS allow.
#include "cdpowder/core/cpu_budget.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <sched.h>

namespace cdpowder {
namespace {

// unsets the cap and reads the budget again when a test ends
struct BudgetRestored {
  ~BudgetRestored() {
    unsetenv(kMaxThreadsVariable);
    unsetenv(kOversubscribeVariable);
    unsetenv(kOpenMpThreadsVariable);
    refresh_usable_cores();
  }
};

TEST(CpuBudget, ZeroAsksForEveryUsableCoreAndNoCountExceedsThem) {
  const BudgetRestored restore;
  const int usable = refresh_usable_cores();
  ASSERT_GE(usable, 1);
  EXPECT_EQ(budgeted_threads(0), usable);
  EXPECT_EQ(budgeted_threads(1), 1);
  EXPECT_EQ(budgeted_threads(1000), usable);
}

TEST(CpuBudget, TheEnvironmentsCapHoldsEveryCount) {
  const BudgetRestored restore;
  setenv(kMaxThreadsVariable, "1", 1);
  EXPECT_EQ(refresh_usable_cores(), 1);
  EXPECT_EQ(budgeted_threads(0), 1);
  EXPECT_EQ(budgeted_threads(2), 1);
  setenv(kMaxThreadsVariable, "not a number", 1);  // ignored, as an unset one
  unsetenv(kMaxThreadsVariable);
  EXPECT_GE(refresh_usable_cores(), 1);
}

// CDPOWDER_OVERSUBSCRIBE=1, read with the budget, grants a positive count as asked (tests of
// the bits on more threads than cores); 0 still means the usable cores.
TEST(CpuBudget, OversubscriptionGrantsTheCountAskedFor) {
  const BudgetRestored restore;
  setenv(kMaxThreadsVariable, "1", 1);
  setenv(kOversubscribeVariable, "1", 1);
  EXPECT_EQ(refresh_usable_cores(), 1);
  EXPECT_EQ(budgeted_threads(4), 4);
  EXPECT_EQ(budgeted_threads(0), 1);
  setenv(kOversubscribeVariable, "yes", 1);  // only "1" oversubscribes
  refresh_usable_cores();
  EXPECT_EQ(budgeted_threads(4), 1);
}

// OMP_NUM_THREADS gives "auto" its count (its first, for the outer level), within the budget;
// an explicit count is not changed by it.
TEST(CpuBudget, OpenMpsThreadCountIsTheCountOfAuto) {
  const BudgetRestored restore;
  setenv(kOversubscribeVariable, "1", 1);
  setenv(kMaxThreadsVariable, "3", 1);
  setenv(kOpenMpThreadsVariable, "2,1", 1);
  refresh_usable_cores();
  const int usable = usable_cores();
  EXPECT_EQ(budgeted_threads(0), std::min(2, usable));
  EXPECT_EQ(budgeted_threads(4), 4);
  setenv(kOpenMpThreadsVariable, "8", 1);
  refresh_usable_cores();
  EXPECT_EQ(budgeted_threads(0), usable);    // never beyond the budget
  setenv(kOpenMpThreadsVariable, "two", 1);  // ignored, as an unset one
  refresh_usable_cores();
  EXPECT_EQ(budgeted_threads(0), usable);
}

// A process given one core (taskset -c 0) runs one thread, whatever it asks for.
TEST(CpuBudget, AnAffinityOfOneCoreGivesOneThread) {
  const BudgetRestored restore;
  cpu_set_t before;
  CPU_ZERO(&before);
  ASSERT_EQ(sched_getaffinity(0, sizeof(before), &before), 0);
  cpu_set_t one;
  CPU_ZERO(&one);
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &before)) {
      CPU_SET(cpu, &one);
      break;
    }
  }
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  EXPECT_EQ(refresh_usable_cores(), 1);
  EXPECT_EQ(budgeted_threads(2), 1);
  ASSERT_EQ(sched_setaffinity(0, sizeof(before), &before), 0);
}

}  // namespace
}  // namespace cdpowder
