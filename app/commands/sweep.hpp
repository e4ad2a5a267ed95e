// sweep.hpp — `cdpowder sweep SWEEP --out DIR`: the parameter studies of docs/sweeps.md.
// Every (point, seed) of the sweep file is one `compact` run in its own process, up to
// --jobs at a time; results.csv and points.csv are rewritten (atomically) after every run.
// Restarting the same command reruns only the runs that have no finished result for
// exactly their scene.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cdpowder::app {

struct SweepOptions {
  std::filesystem::path sweep;         ///< the sweep file (TOML)
  std::filesystem::path out;           ///< output folder
  std::vector<std::string> overrides;  ///< --set: extra fixed overrides of every run
  int jobs = 0;                        ///< runs at a time; 0 = the number of cores
  bool quiet = false;                  ///< no progress lines
  bool dry_run = false;                ///< list the runs and their state, run nothing
  /// --list: print one shell command per run still to do (`… --task I`), run nothing
  bool list = false;
  /// --task I: run exactly run I of the plan (an index --list prints), without the sweep's
  /// folder lock, so that many runners can share the folder
  std::optional<std::size_t> task;
  /// --collect: write results.csv and points.csv from the finished runs, run nothing
  bool collect = false;
  /// --reuse: other sweep folders whose finished runs with exactly a run's scene are copied
  /// in instead of being run again
  std::vector<std::filesystem::path> reuse;
  /// --time-limit [s]: start a run only when it is expected to finish by then
  /// (time_limit.hpp), and stop the runs still going when it has passed
  std::optional<double> time_limit;
  /// --checkpoint-every T [t0]: passed to every run (`cdpowder compact --checkpoint-every`);
  /// an interrupted run with a checkpoint is continued from it (`cdpowder resume`)
  std::optional<double> checkpoint_every;
  /// --stress-bounds: once every run has finished, `cdpowder stress-bounds OUT` (the admissible
  /// stress interval of each blocked run, physics.md §11.3)
  bool stress_bounds = false;
};

/// Checks every run's scene first (ConfigError, nothing written), then runs what is missing.
/// Returns 0 when every run finished, 1 when one failed, the sweep was interrupted
/// (SIGINT/SIGTERM: running runs stop after their step, a second signal kills them) or runs
/// were left for later by the time limit.
int run_sweep(const SweepOptions& options);

}  // namespace cdpowder::app
