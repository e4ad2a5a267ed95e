// stop_signals.hpp — installs a handler for SIGINT, SIGTERM, SIGHUP and SIGUSR1 for the lifetime of
// a command and restores the previous handlers on every exit path, exceptions included. The
// handlers only set atomics; the commands ask them between steps or runs.
//
// A run's handler (request_run_stop): every stop keeps the run. The first signal asks the run
// to stop after its step; it then writes every output and a checkpoint (exit 1). Every later
// signal is part of the same request: GNU timeout and other supervisors signal the process
// and then its group, and a scheduler may follow SIGINT with SIGTERM. Only a SIGINT at least
// a second after the first, a deliberate second Ctrl-C at a terminal, ends the program at
// once (exit 130); the last checkpoint, written atomically, stays.
#pragma once

#include <cstdint>

// sigaction and struct sigaction are POSIX, declared by <signal.h> and not by <csignal>
#include <signal.h>  // NOLINT(modernize-deprecated-headers)

namespace cdpowder::app {

/// How long after the first stop request a SIGINT counts as a deliberate second one [ns].
inline constexpr std::int64_t kDeliberateSecondStop = 1'000'000'000;

/// The run's handler (above); install it with StopSignals(request_run_stop, 0).
extern "C" void request_run_stop(int signal);

/// Whether a stop was asked for since the program started.
bool run_stop_requested();

/// Whether a stop was asked for on any rank of an MPI job (core/ranks.hpp): a collective,
/// asked at the same points of the run on every rank, so that every rank stops after the same
/// pass of the same step. The signal of a Ctrl-C reaches the ranks at different moments.
bool run_stop_requested_on_any_rank();

class StopSignals {
 public:
  /// `flags` are sigaction flags (0: the handler stays for every signal).
  StopSignals(void (*handler)(int), int flags) {
    struct sigaction action {};

    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = flags;
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
    sigaction(SIGHUP, &action, &previous_hup_);
    // Open MPI's mpirun forwards SIGUSR1 to every rank at once (SIGINT and SIGTERM reach them
    // only as its kill sequence): `kill -USR1` on mpirun stops an MPI run as Ctrl-C stops one
    // process
    sigaction(SIGUSR1, &action, &previous_usr1_);
  }

  ~StopSignals() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
    sigaction(SIGHUP, &previous_hup_, nullptr);
    sigaction(SIGUSR1, &previous_usr1_, nullptr);
  }

  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  StopSignals(StopSignals&&) = delete;
  StopSignals& operator=(StopSignals&&) = delete;

 private:
  struct sigaction previous_int_ {};

  struct sigaction previous_term_ {};

  struct sigaction previous_hup_ {};

  struct sigaction previous_usr1_ {};
};

}  // namespace cdpowder::app
