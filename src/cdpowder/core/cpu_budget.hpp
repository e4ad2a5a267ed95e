// cpu_budget.hpp — how many cores this process may run on: its affinity mask (taskset, a
// batch system's cpuset), its CPU quota (a container's cgroup cpu.max) and the cap a parent
// sets in CDPOWDER_MAX_THREADS (a sweep running J runs at once gives each its share). A run
// never spins more threads than this: two threads on one core would wait on each other.
#pragma once

namespace cdpowder {

/// The environment variable that caps the threads of a run (a positive integer).
inline constexpr const char* kMaxThreadsVariable = "CDPOWDER_MAX_THREADS";

/// The environment variable that lets a run spin more threads than its cores ("1"): for
/// tests of the bits at thread counts beyond the machine's cores (mpirun's --oversubscribe).
inline constexpr const char* kOversubscribeVariable = "CDPOWDER_OVERSUBSCRIBE";

/// OpenMP's standard variable: the first of its comma-separated counts is the thread count of
/// `solver.threads = 0` ("auto"), within the budget (a hybrid run of ranks × threads sets it
/// per rank). An explicit count is not changed by it.
inline constexpr const char* kOpenMpThreadsVariable = "OMP_NUM_THREADS";

/// The cores this process may use: the count of its affinity mask (of OpenMP's places when
/// OMP_PROC_BIND binds the threads), at most its CPU quota
/// rounded up, at most kMaxThreadsVariable; at least 1. Read once and kept (a process's
/// budget does not change while it runs); refresh_usable_cores reads it again.
int usable_cores();

/// Reads the budget again (tests that change the affinity).
int refresh_usable_cores();

/// The threads a run asks for (`requested`; 0 for every usable core, or kOpenMpThreadsVariable's
/// count when set) within the budget; a positive count as asked when kOversubscribeVariable was
/// "1" when the budget was read.
int budgeted_threads(int requested);

}  // namespace cdpowder
