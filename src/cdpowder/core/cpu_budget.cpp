// cpu_budget.cpp — sched_getaffinity, the cgroup v2 quota, and the environment's cap.
#include "cdpowder/core/cpu_budget.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

// sched_getaffinity is Linux's
#include <omp.h>
#include <sched.h>

namespace cdpowder {

namespace {

std::atomic<int> g_usable{0};
std::atomic<bool> g_oversubscribe{false};  ///< kOversubscribeVariable, read with the budget
std::atomic<int> g_openmp_threads{0};      ///< kOpenMpThreadsVariable's first count, or 0

int affinity_cores() {
  // With OMP_PROC_BIND set, the OpenMP runtime binds this (the initial) thread to its first
  // place when it starts, before main: the thread's mask is then that place alone. The places
  // were made from the process's mask, so their processors are the ones it may use, counted
  // as the mask counts them: OMP_PLACES=cores gives one place a core, and a runtime that takes
  // two processors for one core's threads (libomp 14 on a 2-core virtual machine) makes one
  // place of both.
  if (omp_get_proc_bind() != omp_proc_bind_false && omp_get_num_places() > 0) {
    int processors = 0;
    for (int place = 0; place < omp_get_num_places(); ++place) {
      processors += omp_get_place_num_procs(place);
    }
    return std::max(1, processors);
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 1;
  return std::max(1, CPU_COUNT(&set));
}

/// The cgroup v2 quota ("max 100000" for none, "150000 100000" for 1.5 cores), rounded up;
/// 0 when there is none or it cannot be read.
int quota_cores() {
  std::ifstream file("/sys/fs/cgroup/cpu.max");
  std::string quota;
  double period = 0.0;
  if (!(file >> quota >> period) || quota == "max" || period <= 0.0) return 0;
  char* end = nullptr;
  const double q = std::strtod(quota.c_str(), &end);
  if (end == quota.c_str() || !(q > 0.0)) return 0;
  return std::max(1, static_cast<int>(std::ceil(q / period)));
}

/// The positive integer that `variable` holds (up to `last`, the end of its text or a comma:
/// OMP_NUM_THREADS may list one count per nesting level), or 0 when unset or not one.
int environment_count(const char* variable, char last) {
  const char* text = std::getenv(variable);
  if (text == nullptr) return 0;
  char* end = nullptr;
  const long count = std::strtol(text, &end, 10);
  const bool whole = end != text && (*end == '\0' || *end == last);
  return whole && count > 0 && count < 1'000'000 ? static_cast<int>(count) : 0;
}

}  // namespace

int refresh_usable_cores() {
  const char* oversubscribe = std::getenv(kOversubscribeVariable);
  g_oversubscribe.store(oversubscribe != nullptr && std::string_view(oversubscribe) == "1");
  int cores = affinity_cores();
  if (const int quota = quota_cores(); quota > 0) cores = std::min(cores, quota);
  if (const int cap = environment_count(kMaxThreadsVariable, '\0'); cap > 0) {
    cores = std::min(cores, cap);
  }
  g_openmp_threads.store(environment_count(kOpenMpThreadsVariable, ','));
  g_usable.store(cores);
  return cores;
}

int usable_cores() {
  const int known = g_usable.load();
  return known > 0 ? known : refresh_usable_cores();
}

int budgeted_threads(int requested) {
  const int usable = usable_cores();  // reads the budget, oversubscription included, once
  if (requested > 0 && g_oversubscribe.load()) return requested;
  if (requested <= 0) {
    const int openmp = g_openmp_threads.load();
    return openmp > 0 ? std::min(openmp, usable) : usable;
  }
  return std::min(requested, usable);
}

}  // namespace cdpowder
