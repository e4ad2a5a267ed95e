// simulate.hpp — `cdpowder simulate SCENE --out DIR` (run a scene for its duration or until
// it blocks) and `cdpowder compact SCENE --out DIR` (the paper's compaction: the piston
// pushes until the blocked state). Both write the same outputs. `cdpowder resume DIR`
// continues either from its checkpoint.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cdpowder::app {

/// Exit codes of a run besides 0 (done) and 2 (bad input, main.cpp); the outputs are
/// written in every case but the last.
inline constexpr int kExitInterrupted = 1;  ///< stopped by a signal: incomplete
inline constexpr int kExitFault = 3;        ///< a fault (run_fault.hpp) ended the run
inline constexpr int kExitNotBlocked = 4;   ///< an until_blocked run reached max_duration
/// An output could not be written (a full disk, a file-size limit, no permission): not
/// written in full; a sweep starts no further run (main.cpp, sweep.cpp).
inline constexpr int kExitOutputFailed = 5;

struct RunOptions {
  std::filesystem::path scene;
  std::filesystem::path out;
  std::vector<std::string> overrides;              ///< --set section.key=value
  std::optional<std::filesystem::path> particles;  ///< --particles: a CSV replaces the scene's
  bool quiet = false;
  /// --checkpoint-every T: keep the state in DIR/checkpoint.cdps, renewed every T of
  /// simulated time [t0]; unset: only when a signal stops the run
  std::optional<double> checkpoint_every;
};

struct ResumeOptions {
  std::filesystem::path folder;  ///< the run's output folder, holding checkpoint.cdps
  bool quiet = false;
  std::optional<double> checkpoint_every;  ///< as RunOptions::checkpoint_every
  /// solver.threads from here on (the bits do not depend on it); unset: the run's own
  std::optional<int> threads;
};

/// Runs the scene and writes to `out`: scene.toml, initial_particles.csv, particles.csv,
/// contacts.csv, timeseries.csv, summary.json, particles.vtp, contacts.vtp, and with
/// [run] snapshot_every > 0 snapshots/ with particles.pvd and contacts.pvd. Prints one
/// result line on stdout. Throws ConfigError for bad input before anything is written.
/// Returns the process exit code: 0 done, kExitInterrupted, kExitFault (also writes
/// failed_state.cdps), kExitNotBlocked.
int run_simulate(const RunOptions& options);

/// As run_simulate, but the scene must have an enabled piston and always runs until the
/// blocked state (or [run] max_duration, after which the summary says it did not block).
int run_compact(const RunOptions& options);

/// `cdpowder resume DIR`: continues the run whose checkpoint.cdps is in DIR, so that it ends
/// bit-identical to the run never stopped (same build): outputs that ran past the checkpoint
/// (time-series rows, snapshots) are cut back to it first, and the run writes every output
/// as run_simulate does. Throws ConfigError when DIR has no checkpoint, StateFileError for
/// a checkpoint of another format or a damaged one; warns on stderr when another build
/// wrote it. Returns the exit code as run_simulate.
int run_resume(const ResumeOptions& options);

}  // namespace cdpowder::app
