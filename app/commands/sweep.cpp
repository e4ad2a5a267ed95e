// sweep.cpp — the sweep command: validate all runs, skip finished ones, run the rest as
// child processes (sweep_pool.hpp), or one of them (--task), or list, collect or show them.
#include "commands/sweep.hpp"

#include "commands/simulate.hpp"
#include "commands/stress_bounds.hpp"
#include "commands/sweep_pool.hpp"
#include "commands/sweep_runs.hpp"
#include "commands/sweep_state.hpp"
#include "die_with_parent.hpp"
#include "stop_signals.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/core/cpu_budget.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/study/sweep_messages.hpp"
#include "cdpowder/study/sweep_plan.hpp"
#include "cdpowder/study/sweep_results.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace cdpowder::app {

namespace {

/// Signals received: the first stops the sweep gracefully, the second kills the runs.
std::atomic<int> g_signals{0};

extern "C" void count_signal(int /*signal*/) {
  g_signals.fetch_add(1);
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
/// sweep lock: the run's own folder lock keeps two runners off one run; a runner that finds
/// it taken leaves the run to its holder and returns 0).
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
  std::filesystem::create_directories(folder);
  // the run's lock before anything of its folder is touched (its log too), passed down to the
  // run: a runner that loses the race writes nothing there, and the run is the winner's
  std::optional<FolderLock> lock;
  try {
    lock.emplace(run_lock_file(folder), "another runner");
  } catch (const OutputError&) {
    throw;
  } catch (const std::runtime_error&) {
    std::fprintf(stderr, "%s\n", run_left_to_its_holder_line(name, folder).c_str());
    return 0;
  }
  // a runner that held the lock until now may have finished the run
  if (finished_summary(plan, folder, state.scene_texts[task])) {
    if (!options.quiet) std::fprintf(stderr, "%s\n", already_finished_line(name).c_str());
    return 0;
  }
  write_file_atomically(options.out / "sweep.toml", read_text(options.sweep));
  signal(SIGCHLD, SIG_DFL);
  setenv(kDieWithParentVariable, std::to_string(getpid()).c_str(), 1);
  std::string why_not;
  const bool resume = has_usable_checkpoint(plan.command, folder, state.scene_texts[task], why_not);
  if (!why_not.empty() && !options.quiet) {
    std::fprintf(stderr, "%s\n", starts_again_line(name, why_not).c_str());
  }
  if (resume && !options.quiet) {
    std::fprintf(stderr, "%s\n", continues_line(name).c_str());
  }
  std::string error;
  const int lock_fd = lock->inheritable_fd();
  const pid_t child = start_run({plan.command, plan.protocol, plan.scene, folder, run.overrides,
                                 options.checkpoint_every, resume, lock_fd},
                                error);
  close(lock_fd);
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
  const std::optional<RunSummary> summary = read_sweep_run(plan, folder);
  const RunExit end = run_exit(status, summary, state.scene_texts[task]);
  const bool unwritten = end.unwritten;
  if (!end.counts || !summary) {
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
  for (const auto& [i, missing] : state.incomplete) {
    std::printf("sweep: %s is incomplete (%s missing): run the sweep again to continue it\n",
                state.plan.runs[i].folder.generic_string().c_str(),
                fmt::format("{}", fmt::join(missing, ", ")).c_str());
  }
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
    const char* what = state.summaries[i]          ? "done   "
                       : state.reused.count(i) > 0 ? "reuse  "
                       : has_usable_checkpoint(plan.command, options.out / plan.runs[i].folder,
                                               state.scene_texts[i], why_not)
                           ? "resume "
                           : "pending";
    const auto incomplete = state.incomplete.find(i);
    const std::string note =
        incomplete == state.incomplete.end()
            ? std::string()
            : fmt::format("  (incomplete: {} missing)", fmt::join(incomplete->second, ", "));
    std::printf("%s  %s%s\n", what, plan.runs[i].folder.generic_string().c_str(), note.c_str());
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
                       : usable_cores();  // the cores this process may use (cpu_budget.hpp)
  if (!options.quiet) {
    const SweepPlan& plan = state.plan;
    std::fprintf(stderr, "%s\n",
                 sweep_start_line(plan.runs.size(), plan.points.size(), plan.seeds.size(),
                                  plan.runs.size() - state.pending.size(), reused_count, jobs)
                     .c_str());
  }
  const int status = run_pending_runs(options, state, jobs, start, g_signals);
  if (status != 0 || !options.stress_bounds) return status;
  return spawn_stress_bounds({options.out.string()}) == 0 ? 0 : 1;
}

}  // namespace cdpowder::app
