// sweep.cpp — the sweep command: validate all runs, skip finished ones, run the rest as
// child processes (`cdpowder compact … --quiet`), collect their summaries.
#include "commands/sweep.hpp"

#include "commands/simulate.hpp"
#include "die_with_parent.hpp"
#include "folder_lock.hpp"
#include "stop_signals.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/run_folder.hpp"
#include "cdpowder/io/state_file.hpp"
#include "cdpowder/sweep/sweep_messages.hpp"
#include "cdpowder/sweep/sweep_plan.hpp"
#include "cdpowder/sweep/sweep_results.hpp"
#include "cdpowder/sweep/time_limit.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <set>
#include <spawn.h>
#include <sstream>
#include <sys/file.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace cdpowder::app {

namespace {

/// Signals received: the first stops the sweep gracefully, the second kills the runs.
std::atomic<int> g_signals{0};

extern "C" void count_signal(int /*signal*/) {
  g_signals.fetch_add(1);
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

/// This program, to run each point as `cdpowder compact`: spawned through /proc/self/exe,
/// which still names this binary after a rebuild has replaced the file on disk (the path
/// it pointed to then no longer starts anything, or starts a different program).
constexpr const char* kSelf = "/proc/self/exe";

/// The running runs: on every exit path (a signal, an exception) they are asked to stop
/// and waited for, so no run outlives the sweep and keeps writing into its folder.
class RunningRuns {
 public:
  RunningRuns() = default;
  RunningRuns(const RunningRuns&) = delete;
  RunningRuns& operator=(const RunningRuns&) = delete;
  RunningRuns(RunningRuns&&) = delete;
  RunningRuns& operator=(RunningRuns&&) = delete;

  ~RunningRuns() {
    for (const auto& entry : runs) kill(entry.first, SIGTERM);
    for (int waited = 0; !runs.empty() && waited < 600; ++waited) {  // ≤ 60 s, then kill
      int status = 0;
      const pid_t pid = waitpid(-1, &status, WNOHANG);
      if (pid > 0) {
        runs.erase(pid);
      } else if (pid < 0 && errno == ECHILD) {
        break;
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    }
    for (const auto& entry : runs) kill(entry.first, SIGKILL);
    for (const auto& entry : runs) waitpid(entry.first, nullptr, 0);
  }

  std::map<pid_t, std::size_t> runs;  ///< process → index of the run in the plan
};

/// Whether the unfinished run in `folder` can be continued from its checkpoint: there is
/// one, of this build's format, for exactly the run's scene. Otherwise the run starts again
/// (which clears the folder); `why_not` then says why a checkpoint there was not used.
bool has_usable_checkpoint(const std::filesystem::path& folder, const std::string& scene_text,
                           std::string& why_not) {
  const std::filesystem::path file = checkpoint_path(folder);
  if (!std::filesystem::exists(file)) return false;
  try {
    const StateHeader header = read_state_header(file);
    if (header.format_version != kStateFormatVersion) {
      why_not = fmt::format("its checkpoint is of state format {}, this build reads format {}",
                            header.format_version, kStateFormatVersion);
      return false;
    }
    if (header.scene_toml != scene_text) {
      why_not = "its checkpoint is of another scene";
      return false;
    }
    return true;
  } catch (const StateFileError& error) {
    why_not = error.what();
    return false;
  }
}

/// How a sweep starts a run: `cdpowder compact scene --out folder --quiet --set …`, or, for
/// an unfinished run with a usable checkpoint, `cdpowder resume folder --quiet`.
struct RunStart {
  const std::filesystem::path& scene;
  const std::filesystem::path& folder;
  const std::vector<SceneOverride>& overrides;
  std::optional<double> checkpoint_every;
  bool resume = false;
};

/// Starts the run in its own process group (so a Ctrl-C reaches only the sweep, which
/// forwards one SIGTERM), stdout and stderr into folder/log.txt (appended to when the run is
/// continued, so the log keeps its history).
/// Returns the process id, or 0 (with `error` set) when it could not be started.
pid_t start_run(const RunStart& run, std::string& error) {
  const std::filesystem::path& folder = run.folder;
  std::vector<std::string> args{"cdpowder", "resume", folder.string(), "--quiet"};
  if (!run.resume) {
    args = {"cdpowder", "compact", run.scene.string(), "--out", folder.string(), "--quiet"};
    for (const SceneOverride& o : run.overrides) {
      args.emplace_back("--set");
      args.push_back(o.text);
    }
  }
  if (run.checkpoint_every) {
    args.emplace_back("--checkpoint-every");
    args.push_back(fmt::format("{}", *run.checkpoint_every));
  }
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  const std::string log = (folder / "log.txt").string();
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | (run.resume ? O_APPEND : O_TRUNC), 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, kSelf, &files, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  if (failed != 0) {
    error = fmt::format("cannot start {}: {}", kSelf, std::strerror(failed));
    return 0;
  }
  return pid;
}

std::string sweep_header(const SweepPlan& plan) {
  return fmt::format("# cdpowder {} (commit {})\n# sweep: {}\n# scene: {}\n", kVersion, kGitCommit,
                     plan.source.string(), plan.scene.string());
}

void write_tables(const SweepOptions& options, const SweepPlan& plan,
                  const std::vector<std::optional<RunSummary>>& summaries) {
  const std::string header = sweep_header(plan);
  write_file_atomically(options.out / "results.csv", results_csv(plan, summaries, header));
  write_file_atomically(options.out / "points.csv", points_csv(plan, summaries, header));
}

/// As write_tables, while runs go on: the failure's message ("cannot write …: No space left
/// on device"), or "" when both tables were written.
std::string try_write_tables(const SweepOptions& options, const SweepPlan& plan,
                             const std::vector<std::optional<RunSummary>>& summaries) {
  try {
    write_tables(options, plan, summaries);
  } catch (const OutputError& error) {
    return error.what();
  }
  return {};
}

/// How a run's process ended (its wait status), read the same way by the sweep's loop and by
/// --task.
struct RunExit {
  bool fault = false;      ///< exit kExitFault: a fault stopped it
  bool unwritten = false;  ///< exit kExitOutputFailed: an output could not be written
  /// Its results count: it ended (a compaction that did not block is finished, blocked = 0
  /// in the tables), or an output failed after its summary was written (the time series, at
  /// the end), and the summary is one of this run's scene.
  bool counts = false;
};

RunExit run_exit(int status, const std::optional<RunSummary>& summary,
                 const std::string& scene_text) {
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  RunExit out;
  out.fault = code == kExitFault;
  out.unwritten = code == kExitOutputFailed;
  out.counts =
      (code == 0 || code == kExitNotBlocked || out.unwritten) && is_reusable(summary, scene_text);
  return out;
}

/// The last "error: …" line of a run's log (what made it fail), without the prefix; `log`
/// itself when there is none.
std::string last_error_of(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line;
  std::string last;
  while (std::getline(in, line)) {
    if (line.starts_with("error: ")) last = line.substr(7);
  }
  return last.empty() ? "a run could not write its outputs, see " + log.string() : last;
}

/// What a sweep folder holds against its plan: every run's resolved scene, the finished
/// runs' summaries, and the runs still to do (those another sweep has done, with --reuse,
/// apart).
struct SweepState {
  SweepPlan plan;
  std::vector<std::string> scene_texts;
  std::vector<std::optional<RunSummary>> summaries;
  std::vector<std::size_t> pending;
  std::map<std::size_t, std::filesystem::path> reused;
};

/// Reads the plan, checks every run's scene (ConfigError, nothing written) and what DIR
/// already holds.
SweepState read_sweep_state(const SweepOptions& options) {
  SweepState state{read_sweep_plan(options.sweep, options.overrides), {}, {}, {}, {}};
  const SweepPlan& plan = state.plan;
  std::vector<std::string>& scene_texts = state.scene_texts;
  scene_texts.resize(plan.runs.size());
  // every run's scene is checked before anything starts; each distinct mistake once
  std::vector<ConfigIssue> issues;
  std::set<std::string> seen;
  SceneReadOptions compaction;
  compaction.compaction = true;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    try {
      scene_texts[i] = read_scene(plan.scene, plan.runs[i].overrides, compaction).effective_toml;
    } catch (const ConfigError& error) {
      for (const ConfigIssue& issue : error.issues()) {
        if (seen.insert(format(issue)).second) issues.push_back(issue);
      }
    }
  }
  // two points that resolve to the same scene (e.g. 1 and 1.0, or a value equal to the
  // base scene's) would run the same thing twice under two names
  std::map<std::string, std::size_t> first_with_scene;
  for (std::size_t i = 0; issues.empty() && i < plan.runs.size(); ++i) {
    const auto [it, fresh] = first_with_scene.emplace(scene_texts[i], i);
    if (!fresh) {
      issues.push_back({plan.source.string(), 0, 0, "",
                        fmt::format("points '{}' and '{}' give the same scene (seed {}); "
                                    "list each point once",
                                    plan.points[plan.runs[it->second].point].name,
                                    plan.points[plan.runs[i].point].name, plan.runs[i].seed)});
    }
  }
  if (!issues.empty()) throw ConfigError(std::move(issues));

  std::vector<std::optional<RunSummary>>& summaries = state.summaries;
  summaries.resize(plan.runs.size());
  std::vector<std::size_t>& pending = state.pending;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    std::optional<RunSummary> summary =
        read_run_summary(options.out / plan.runs[i].folder / "summary.json");
    if (is_reusable(summary, scene_texts[i])) {
      summaries[i] = std::move(summary);
    } else {
      pending.push_back(i);
    }
  }
  // runs another sweep has already done, for exactly the same scene
  std::map<std::size_t, std::filesystem::path>& reused = state.reused;
  if (!options.reuse.empty()) {
    std::map<std::string, std::filesystem::path> elsewhere;
    for (const std::filesystem::path& folder : options.reuse) {
      std::map<std::string, std::filesystem::path> found = finished_runs_by_scene(folder);
      if (found.empty() && !options.quiet) {
        std::fprintf(stderr, "%s\n", nothing_to_reuse_line(folder).c_str());
      }
      elsewhere.merge(found);
    }
    std::vector<std::size_t> still_pending;
    for (const std::size_t i : pending) {
      const auto found = elsewhere.find(scene_texts[i]);
      if (found == elsewhere.end()) {
        still_pending.push_back(i);
      } else {
        reused.emplace(i, found->second);
      }
    }
    pending.swap(still_pending);
  }
  order_seed_by_seed(plan, pending);
  return state;
}

/// `text` quoted for a POSIX shell.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

/// --list: one shell command per pending run, each `cdpowder sweep … --task I` with the
/// run's index in the full plan (stable: the plan's order) and folder beside it.
int list_pending_runs(const SweepOptions& options, const SweepState& state) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink(kSelf, error);
  std::string common = shell_quoted(error ? std::string("cdpowder") : self.string()) + " sweep " +
                       shell_quoted(std::filesystem::absolute(options.sweep).string()) + " --out " +
                       shell_quoted(std::filesystem::absolute(options.out).string());
  for (const std::string& o : options.overrides) common += " --set " + shell_quoted(o);
  if (options.checkpoint_every) {
    common += fmt::format(" --checkpoint-every {}", *options.checkpoint_every);
  }
  std::vector<std::size_t> listed = state.pending;
  for (const auto& entry : state.reused) listed.push_back(entry.first);
  std::sort(listed.begin(), listed.end());
  for (const std::size_t i : listed) {
    std::printf("%s --task %zu --quiet  # run %zu: %s\n", common.c_str(), i, i,
                state.plan.runs[i].folder.generic_string().c_str());
  }
  return 0;
}

/// --task I: run I of the plan and nothing else, as one of many runners on the folder (no
/// sweep lock: the run's own folder lock keeps two runners off one run).
int run_task(const SweepOptions& options, const SweepState& state, std::size_t task) {
  const SweepPlan& plan = state.plan;
  if (task >= plan.runs.size()) {
    throw ConfigError({{"--task", 0, 0, "",
                        fmt::format("got {}, expected a run index from 0 to {} (--list prints "
                                    "them)",
                                    task, plan.runs.size() - 1)}});
  }
  const SweepRun& run = plan.runs[task];
  const std::filesystem::path folder = options.out / run.folder;
  const std::string name =
      fmt::format("run {} ({})", task, sweep_run_name(plan.points[run.point].name, run.seed));
  if (state.summaries[task]) {
    if (!options.quiet) std::fprintf(stderr, "%s\n", already_finished_line(name).c_str());
    return 0;
  }
  if (FolderLock::held(run_lock_file(folder))) {
    std::fprintf(stderr, "%s\n", run_folder_busy_line(name, folder, false).c_str());
    return 1;
  }
  std::filesystem::create_directories(folder);
  write_file_atomically(options.out / "sweep.toml", read_text(options.sweep));
  signal(SIGCHLD, SIG_DFL);
  setenv(kDieWithParentVariable, std::to_string(getpid()).c_str(), 1);
  std::string why_not;
  const bool resume = has_usable_checkpoint(folder, state.scene_texts[task], why_not);
  if (!why_not.empty() && !options.quiet) {
    std::fprintf(stderr, "%s\n", starts_again_line(name, why_not).c_str());
  }
  if (resume && !options.quiet) {
    std::fprintf(stderr, "%s\n", continues_line(name).c_str());
  }
  std::string error;
  const pid_t child =
      start_run({plan.scene, folder, run.overrides, options.checkpoint_every, resume}, error);
  if (child == 0) throw std::runtime_error(error);
  int status = 0;
  bool asked_to_stop = false;
  while (waitpid(child, &status, WNOHANG) == 0) {
    if (g_signals.load() > 0 && !asked_to_stop) {  // a scheduler's SIGTERM: the run stops too
      kill(child, SIGTERM);
      asked_to_stop = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::optional<RunSummary> summary = read_run_summary(folder / "summary.json");
  const RunExit end = run_exit(status, summary, state.scene_texts[task]);
  const bool unwritten = end.unwritten;
  if (!end.counts) {
    std::fprintf(stderr, "%s\n",
                 unfinished_run_line(name, unfinished_run_text(asked_to_stop, end.fault, unwritten),
                                     folder / "log.txt")
                     .c_str());
    // a scheduler's array then sees the machine's failure apart from the run's
    return unwritten ? kExitOutputFailed : 1;
  }
  if (!options.quiet) {
    std::fprintf(stderr, "%s\n", finished_run_line(name, *summary, unwritten).c_str());
  }
  return unwritten ? kExitOutputFailed : 0;
}

/// --collect: the tables of what has finished, starting nothing.
int collect_tables(const SweepOptions& options, const SweepState& state) {
  std::filesystem::create_directories(options.out);
  write_tables(options, state.plan, state.summaries);
  const auto finished = static_cast<std::size_t>(
      std::count_if(state.summaries.begin(), state.summaries.end(),
                    [](const std::optional<RunSummary>& r) { return r.has_value(); }));
  std::printf("sweep: %zu of %zu runs finished; results in %s\n", finished, state.plan.runs.size(),
              (options.out / "results.csv").string().c_str());
  return 0;
}

/// --dry-run: what each run would do, nothing started or written.
int print_dry_run(const SweepOptions& options, const SweepState& state) {
  const SweepPlan& plan = state.plan;
  const std::size_t total = plan.runs.size();
  std::printf("%zu runs (%zu points × %zu seeds), %zu finished, %zu reused, %zu to run\n", total,
              plan.points.size(), plan.seeds.size(),
              total - state.pending.size() - state.reused.size(), state.reused.size(),
              state.pending.size());
  for (std::size_t i = 0; i < total; ++i) {
    std::string why_not;
    const char* what =
        state.summaries[i]          ? "done   "
        : state.reused.count(i) > 0 ? "reuse  "
        : has_usable_checkpoint(options.out / plan.runs[i].folder, state.scene_texts[i], why_not)
            ? "resume "
            : "pending";
    std::printf("%s  %s\n", what, plan.runs[i].folder.generic_string().c_str());
  }
  return 0;
}

/// Copies the summaries of the runs another sweep has done (--reuse) into their folders here;
/// a copy that does not read back goes to the pending runs. Returns how many were reused.
std::size_t adopt_reused_runs(const SweepOptions& options, SweepState& state) {
  std::size_t reused_count = 0;
  for (const auto& [i, source] : state.reused) {
    // an earlier, unfinished attempt may have left its outputs here: they are not this run's
    const std::filesystem::path folder = options.out / state.plan.runs[i].folder;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    write_file_atomically(folder / "summary.json", read_text(source));
    write_file_atomically(folder / "log.txt",
                          fmt::format("reused from {}\n", source.string()));  // as --reuse named it
    state.summaries[i] = read_run_summary(folder / "summary.json");
    if (is_reusable(state.summaries[i], state.scene_texts[i])) {
      ++reused_count;
    } else {  // the copy failed: run it after all
      state.summaries[i].reset();
      state.pending.push_back(i);
      if (!options.quiet) {
        std::fprintf(stderr, "%s\n", could_not_reuse_line(source).c_str());
      }
    }
  }
  order_seed_by_seed(state.plan, state.pending);
  return reused_count;
}

/// The pending runs as child processes, `jobs` at a time: started while no stop is asked
/// for, no write has failed and (with --time-limit) each is expected to finish in time;
/// reaped as they end, with a progress line each and the tables rewritten.
class SweepPool {
 public:
  SweepPool(const SweepOptions& options, SweepState& state,
            std::chrono::steady_clock::time_point start)
      : options_(options), state_(state), start_(start) {}

  /// Runs until every pending run has ended or been left (a signal, the time limit, a
  /// write error); the running runs are stopped and waited for on every exit path.
  void run(int jobs) {
    while (next_ < state_.pending.size() || !guard_.runs.empty()) {
      const int received = g_signals.load();
      check_time_limit();
      send_stop_requests(received);
      if (received == 0) start_runs(jobs);
      if ((received > 0 || time_up_ || !write_error_.empty()) && guard_.runs.empty()) break;
      reap_one();
    }
    if (std::string error = try_write_tables(options_, state_.plan, state_.summaries);
        !error.empty() && write_error_.empty()) {
      write_error_ = std::move(error);
    }
  }

  /// The last line: how many finished, and why the others did not; the exit code.
  int finish() const {
    SweepTally tally;
    tally.total = state_.plan.runs.size();
    tally.finished = tally.total - state_.pending.size() + done_now_;
    tally.failed = failed_;
    tally.held_elsewhere = held_elsewhere_;
    tally.interrupted = g_signals.load() > 0;
    if (left_for_later_ > 0 || time_up_) tally.time_limit_reached = options_.time_limit;
    tally.write_error = write_error_;
    tally.not_started = state_.pending.size() > next_ ? state_.pending.size() - next_ : 0;
    std::printf("%s\n", sweep_end_line(tally, options_.out / "results.csv").c_str());
    if (!write_error_.empty()) return kExitOutputFailed;
    return tally.finished == tally.total ? 0 : 1;
  }

 private:
  [[nodiscard]] double seconds_since_start() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  [[nodiscard]] std::string run_name(std::size_t i) const {
    const SweepRun& run = state_.plan.runs[i];
    return sweep_run_name(state_.plan.points[run.point].name, run.seed);
  }

  /// Past the limit nothing more starts, and runs still going stop as at a first Ctrl-C
  /// (the expected durations should have left none).
  void check_time_limit() {
    if (!options_.time_limit || time_up_ || seconds_since_start() < *options_.time_limit) return;
    time_up_ = true;
    left_for_later_ += state_.pending.size() - next_;
    next_ = state_.pending.size();
  }

  /// How hard the running runs are asked to stop: 0 not, 1 SIGTERM (a run finishes its step,
  /// writes its outputs flagged interrupted, and is rerun next time), 2 SIGKILL. A run
  /// handles one SIGTERM and dies at a second, so each level is sent once, whether a signal
  /// to the sweep or the time limit asked for it. A run asked to stop ends within a step; one
  /// still going a minute after the limit is killed, so the sweep keeps to its limit.
  void send_stop_requests(int received) {
    const bool overdue = time_up_ && seconds_since_start() >= *options_.time_limit + 60.0;
    const int level = std::min(2, std::max({received, time_up_ ? 1 : 0, overdue ? 2 : 0}));
    if (level <= stop_level_sent_) return;
    for (const auto& [pid, index] : guard_.runs) kill(pid, level >= 2 ? SIGKILL : SIGTERM);
    stop_level_sent_ = level;
  }

  /// A write error (a run's exit kExitOutputFailed, or the sweep's own tables) would fail
  /// every later run the same way (a full disk): nothing more starts after one.
  void start_runs(int jobs) {
    while (write_error_.empty() && next_ < state_.pending.size() &&
           static_cast<int>(guard_.runs.size()) < jobs) {
      start_run_at(state_.pending[next_++]);
    }
  }

  void start_run_at(std::size_t i) {
    if (options_.time_limit &&
        !may_start_within(seconds_since_start(),
                          expected_run_seconds(state_.plan, state_.summaries, i),
                          *options_.time_limit)) {
      ++left_for_later_;
      return;
    }
    const SweepRun& run = state_.plan.runs[i];
    const std::filesystem::path folder = options_.out / run.folder;
    // a process of an earlier sweep still writing into the folder (it got SIGTERM when that
    // sweep died, and is finishing its step): left for the next run of this command
    if (FolderLock::held(run_lock_file(folder))) {
      ++held_elsewhere_;
      std::fprintf(stderr, "%s\n", run_folder_busy_line(run_name(i), folder, true).c_str());
      return;
    }
    std::error_code made;
    std::filesystem::create_directories(folder, made);
    if (made) {  // a full disk: no run can start; the running ones end as they can
      write_error_ = fmt::format("cannot create {}: {}", folder.string(), made.message());
      --next_;
      return;
    }
    // an interrupted run goes on from its checkpoint instead of starting again
    std::string why_not;
    const bool resume = has_usable_checkpoint(folder, state_.scene_texts[i], why_not);
    if (!why_not.empty() && !options_.quiet) {
      std::fprintf(stderr, "%s\n", starts_again_line(run_name(i), why_not).c_str());
    }
    std::string error;
    const pid_t child = start_run(
        {state_.plan.scene, folder, run.overrides, options_.checkpoint_every, resume}, error);
    if (child == 0) {
      ++failed_;
      std::fprintf(stderr, "%s\n", run_not_started_line(run_name(i), error).c_str());
      return;
    }
    guard_.runs[child] = i;
  }

  /// Waits up to 0.1 s for a run to end, and takes its result.
  void reap_one() {
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid < 0 && errno == ECHILD) {  // nothing left to wait for: the bookkeeping is stale
      guard_.runs.clear();
      return;
    }
    if (pid <= 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      return;
    }
    const auto it = guard_.runs.find(pid);
    if (it == guard_.runs.end()) return;
    const std::size_t i = it->second;
    guard_.runs.erase(it);
    const std::filesystem::path folder = options_.out / state_.plan.runs[i].folder;
    std::optional<RunSummary> summary = read_run_summary(folder / "summary.json");
    const RunExit end = run_exit(status, summary, state_.scene_texts[i]);
    if (end.unwritten && write_error_.empty()) write_error_ = last_error_of(folder / "log.txt");
    if (end.counts) {
      state_.summaries[i] = std::move(summary);
      ++done_now_;
      if (std::string error = try_write_tables(options_, state_.plan, state_.summaries);
          !error.empty() && write_error_.empty()) {
        write_error_ = std::move(error);
      }
    } else if (g_signals.load() == 0 && !time_up_) {
      ++failed_;
    }
    if (!options_.quiet) report(i, end, folder);
  }

  /// "[7/80] point seed 2: porosity=… blocked=yes wall=…s (elapsed 03:10, ≈27:00 left)".
  void report(std::size_t i, const RunExit& end, const std::filesystem::path& folder) const {
    const bool stopped = g_signals.load() > 0 || time_up_;
    const double elapsed = seconds_since_start();
    const std::size_t total = state_.plan.runs.size();
    const std::size_t finished = total - state_.pending.size() + done_now_;
    const std::size_t left =
        state_.pending.size() - done_now_ - failed_ - left_for_later_ - held_elsewhere_;
    // throughput so far (runs finished per wall second, all jobs together) × runs left
    const std::optional<double> eta =
        done_now_ > 0 && !stopped
            ? std::optional(elapsed * static_cast<double>(left) / static_cast<double>(done_now_))
            : std::nullopt;
    const std::string line =
        end.counts ? finished_run_progress(finished, total, run_name(i), *state_.summaries[i],
                                           elapsed, eta, end.unwritten)
                   : unfinished_run_progress(finished, total, run_name(i),
                                             unfinished_run_text(stopped, end.fault, end.unwritten),
                                             folder / "log.txt");
    std::fprintf(stderr, "%s\n", line.c_str());
  }

  const SweepOptions& options_;
  SweepState& state_;
  std::chrono::steady_clock::time_point start_;
  RunningRuns guard_;
  std::size_t next_ = 0;
  std::size_t done_now_ = 0;
  std::size_t failed_ = 0;
  std::size_t left_for_later_ = 0;  ///< not started: not expected to finish within the limit
  std::size_t held_elsewhere_ = 0;  ///< not started: an earlier process still writes its folder
  bool time_up_ = false;
  std::string write_error_;
  int stop_level_sent_ = 0;
};

}  // namespace

int run_sweep(const SweepOptions& options) {
  // --time-limit counts from here, the command's start, as a batch system's limit would
  const auto start = std::chrono::steady_clock::now();
  const StopSignals signals(count_signal, 0);  // no SA_RESETHAND: the second signal is counted
  g_signals.store(0);
  SweepState state = read_sweep_state(options);
  if (options.list) return list_pending_runs(options, state);
  if (options.task) return run_task(options, state, *options.task);
  if (options.collect) return collect_tables(options, state);
  if (options.dry_run) return print_dry_run(options, state);

  std::filesystem::create_directories(options.out);
  const FolderLock lock(options.out / ".lock", "another sweep");
  // the runs are this process's children: waitpid must see them (an inherited SIG_IGN for
  // SIGCHLD would let the kernel reap them unseen)
  signal(SIGCHLD, SIG_DFL);
  // the runs end (as at Ctrl-C) when this process dies, even by SIGKILL (main.cpp)
  setenv(kDieWithParentVariable, std::to_string(getpid()).c_str(), 1);
  write_file_atomically(options.out / "sweep.toml", read_text(options.sweep));
  const std::size_t reused_count = adopt_reused_runs(options, state);
  write_tables(options, state.plan, state.summaries);

  const int jobs = options.jobs > 0
                       ? options.jobs
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (!options.quiet) {
    const SweepPlan& plan = state.plan;
    std::fprintf(stderr, "%s\n",
                 sweep_start_line(plan.runs.size(), plan.points.size(), plan.seeds.size(),
                                  plan.runs.size() - state.pending.size(), reused_count, jobs)
                     .c_str());
  }
  SweepPool pool(options, state, start);
  pool.run(jobs);
  return pool.finish();
}

}  // namespace cdpowder::app
