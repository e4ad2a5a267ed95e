// stop_signals.hpp — installs a handler for SIGINT, SIGTERM and SIGHUP for the lifetime of a
// command and restores the previous handlers on every exit path, exceptions included.
// The handlers only set atomics; the commands ask them between steps or runs.
#pragma once

// sigaction and struct sigaction are POSIX, declared by <signal.h> and not by <csignal>
#include <signal.h>  // NOLINT(modernize-deprecated-headers)

namespace cdpowder::app {

class StopSignals {
 public:
  /// `flags` are sigaction flags, e.g. SA_RESETHAND for a one-shot handler (a second
  /// Ctrl-C then ends the program at once).
  StopSignals(void (*handler)(int), int flags) {
    struct sigaction action {};

    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = flags;
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
    sigaction(SIGHUP, &action, &previous_hup_);
  }

  ~StopSignals() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
    sigaction(SIGHUP, &previous_hup_, nullptr);
  }

  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  StopSignals(StopSignals&&) = delete;
  StopSignals& operator=(StopSignals&&) = delete;

 private:
  struct sigaction previous_int_ {};

  struct sigaction previous_term_ {};

  struct sigaction previous_hup_ {};
};

}  // namespace cdpowder::app
