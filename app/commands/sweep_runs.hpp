// sweep_runs.hpp — a sweep's runs as child processes of this program (`cdpowder compact …`,
// or `cdpowder resume …` for a run with a usable checkpoint), and how each one ended. Used
// by the pool of a sweep (sweep_pool.hpp) and by --task (sweep.cpp).
#pragma once

#include "cdpowder/config/scene_override.hpp"
#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/study/sweep_plan.hpp"

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace cdpowder::app {

/// This program, to run each point as `cdpowder compact`: spawned through /proc/self/exe,
/// which still names this binary after a rebuild has replaced the file on disk (the path
/// it pointed to then no longer starts anything, or starts a different program).
inline constexpr const char* kSelf = "/proc/self/exe";

/// The running runs: on every exit path (a signal, an exception) they are asked to stop
/// and waited for, so no run outlives the sweep and keeps writing into its folder.
class RunningRuns {
 public:
  RunningRuns() = default;
  RunningRuns(const RunningRuns&) = delete;
  RunningRuns& operator=(const RunningRuns&) = delete;
  RunningRuns(RunningRuns&&) = delete;
  RunningRuns& operator=(RunningRuns&&) = delete;

  ~RunningRuns();

  std::map<pid_t, std::size_t> runs;  ///< process → index of the run in the plan
};

/// Whether the unfinished run in `folder` can be continued from its checkpoint: there is
/// one, of this build's format, for exactly the run's scene. Otherwise the run starts again
/// (which clears the folder); `why_not` then says why a checkpoint there was not used. A
/// Python protocol's run always starts again.
bool has_usable_checkpoint(SweepCommand command, const std::filesystem::path& folder,
                           const std::string& scene_text, std::string& why_not);

/// How a sweep starts a run: `cdpowder compact scene --out folder --quiet --set …`, or, for
/// an unfinished run with a usable checkpoint, `cdpowder resume folder --quiet`; a Python
/// protocol as `python3 -m cdpowder.protocol FILE FUNCTION scene --out folder --set …`.
struct RunStart {
  SweepCommand command = SweepCommand::Compact;  ///< a fresh run's (a resumed one is `resume`)
  const SweepProtocol& protocol;                 ///< with command Python
  const std::filesystem::path& scene;
  const std::filesystem::path& folder;
  const std::vector<SceneOverride>& overrides;
  std::optional<double> checkpoint_every;
  bool resume = false;
  /// the run's folder lock, taken by the caller before anything touches the folder
  /// (FolderLock::inheritable_fd): the run adopts it (kInheritedLockVariable)
  int lock_fd = -1;
  /// the cores the run may use (kMaxThreadsVariable), when it shares the machine with other
  /// runs of the sweep; 0 leaves the environment's setting, or none
  int max_threads = 0;
};

/// Starts the run in its own process group (so a Ctrl-C reaches only the sweep, which
/// forwards one SIGTERM), stdout and stderr into folder/log.txt (appended to when the run is
/// continued, so the log keeps its history), holding the lock the caller took for it.
/// Returns the process id, or 0 (with `error` set) when it could not be started.
pid_t start_run(const RunStart& run, std::string& error);

/// How a run's process ended (its wait status), read the same way by the sweep's loop and by
/// --task.
struct RunExit {
  bool fault = false;      ///< exit kExitFault: a fault stopped it
  bool unwritten = false;  ///< exit kExitOutputFailed: an output could not be written
  /// Its results count: it ended (a compaction that did not block is finished, blocked = 0
  /// in the tables) with every output written, and the summary is one of this run's scene. A
  /// run whose output failed is not finished: it runs again when the sweep can write.
  bool counts = false;
};

/// A run's summary as the sweep compares it with the point (is_reusable): summary.json, and
/// for a Python protocol with the point's scene from protocol.json in place of the last scene
/// the protocol ran (nothing until the protocol has returned, or for another protocol).
std::optional<RunSummary> read_sweep_run(const SweepPlan& plan,
                                         const std::filesystem::path& folder);

/// Reads a run's wait status, summary and scene the same way for the pool and for --task.
RunExit run_exit(int status, const std::optional<RunSummary>& summary,
                 const std::string& scene_text);

/// The last "error: …" line of a run's log (what made it fail), without the prefix; `log`
/// itself when there is none.
std::string last_error_of(const std::filesystem::path& log);

}  // namespace cdpowder::app
