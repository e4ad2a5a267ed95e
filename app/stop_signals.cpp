// stop_signals.cpp — the run's stop request as a signal handler may set it: atomics, the
// monotonic clock and write(2), all async-signal-safe.
#include "stop_signals.hpp"

#include "cdpowder/core/ranks.hpp"

#include <atomic>
#include <cstdint>
#include <ctime>
#include <string_view>
#include <unistd.h>

namespace cdpowder::app {

namespace {

std::atomic<bool> g_requested{false};
std::atomic<std::int64_t> g_first_ns{0};

/// Nanoseconds of the monotonic clock (clock_gettime is async-signal-safe).
std::int64_t now_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

void say(std::string_view text) {
  // the result is ignored: nothing can be done about a closed stderr inside a handler
  const ssize_t written = write(STDERR_FILENO, text.data(), text.size());
  static_cast<void>(written);
}

constexpr std::string_view kStopping =
    "\nstopping: the run ends after its step and writes every output and a checkpoint "
    "(a second Ctrl-C, a second or more from now, ends it at once)\n";
constexpr std::string_view kQuitting =
    "\nsecond Ctrl-C: ending at once; the last checkpoint stays as it was\n";

}  // namespace

extern "C" void request_run_stop(int signal) {
  const std::int64_t now = now_ns();
  // the first signal's time and the request in one step: a second signal handled at once on
  // another thread (timeout signals the process and then its group) finds the time already
  // there, never 0
  std::int64_t first = 0;
  if (g_first_ns.compare_exchange_strong(first, now)) {
    g_requested.store(true);
    say(kStopping);
    return;
  }
  // the same request again (timeout signals the process and its group; a scheduler follows
  // SIGINT with SIGTERM), unless it is a deliberate second Ctrl-C
  if (signal == SIGINT && now - first >= kDeliberateSecondStop) {
    say(kQuitting);
    _exit(130);  // 128 + SIGINT, as the shell reports a program ended by it
  }
}

bool run_stop_requested() {
  return g_requested.load();
}

bool run_stop_requested_on_any_rank() {
  return any_rank(g_requested.load());
}

}  // namespace cdpowder::app
