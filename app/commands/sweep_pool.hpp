// sweep_pool.hpp — the pending runs of a sweep as child processes, --jobs at a time.
#pragma once

#include "commands/sweep.hpp"
#include "commands/sweep_state.hpp"

#include <atomic>
#include <chrono>

namespace cdpowder::app {

/// Runs the pending runs of `state`, `jobs` at a time, until each has ended or been left (a
/// signal counted in `signals`, the time limit counted from `start`, a write error); prints a
/// line per run and the sweep's last line. Returns the command's exit code: 0 when every run
/// finished, kExitOutputFailed after a write error, 1 otherwise.
int run_pending_runs(const SweepOptions& options, SweepState& state, int jobs,
                     std::chrono::steady_clock::time_point start, const std::atomic<int>& signals);

}  // namespace cdpowder::app
