// sweep_pool.cpp — started while no stop is asked for, no write has failed and (with
// --time-limit) each is expected to finish in time; reaped as they end.
#include "commands/sweep_pool.hpp"

#include "commands/simulate.hpp"
#include "commands/sweep_runs.hpp"

#include "cdpowder/core/cpu_budget.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/study/sweep_messages.hpp"
#include "cdpowder/study/sweep_results.hpp"
#include "cdpowder/study/time_limit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <optional>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <utility>

namespace cdpowder::app {

namespace {

/// The pending runs as child processes, `jobs` at a time: started while no stop is asked
/// for, no write has failed and (with --time-limit) each is expected to finish in time;
/// reaped as they end, with a progress line each and the tables rewritten.
class SweepPool {
 public:
  SweepPool(const SweepOptions& options, SweepState& state,
            std::chrono::steady_clock::time_point start, const std::atomic<int>& signals)
      : options_(options), state_(state), start_(start), signals_(signals) {}

  /// Runs until every pending run has ended or been left (a signal, the time limit, a
  /// write error); the running runs are stopped and waited for on every exit path.
  void run(int jobs) {
    // J runs at once share the cores: each may use its part (at least one)
    threads_per_run_ = jobs > 1 ? std::max(1, usable_cores() / jobs) : 0;
    while (next_ < state_.pending.size() || !guard_.runs.empty()) {
      const int received = signals_.load();
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
    tally.interrupted = signals_.load() > 0;
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
    const bool overdue =
        time_up_ && options_.time_limit && seconds_since_start() >= *options_.time_limit + 60.0;
    const int level = std::min(2, std::max({received, time_up_ ? 1 : 0, overdue ? 2 : 0}));
    if (level <= stop_level_sent_) return;
    for (const auto& [pid, index] : guard_.runs) kill(pid, level >= 2 ? SIGKILL : SIGTERM);
    stop_level_sent_ = level;
  }

  /// A write error (a run's exit kExitOutputFailed, or the sweep's own tables) would fail
  /// every later run the same way (a full disk): nothing more starts after one.
  void start_runs(int jobs) {
    while (write_error_.empty() && next_ < state_.pending.size() &&
           std::cmp_less(guard_.runs.size(), jobs)) {
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
    std::error_code made;
    std::filesystem::create_directories(folder, made);
    if (made) {  // a full disk: no run can start; the running ones end as they can
      write_error_ = fmt::format("cannot create {}: {}", folder.string(), made.message());
      --next_;
      return;
    }
    // the run's lock, taken here and passed down, before anything of its folder is touched;
    // taken by another process (an earlier sweep's run finishing its step after a SIGTERM,
    // or an outside runner): left for the next run of this command
    std::optional<FolderLock> lock;
    try {
      lock.emplace(run_lock_file(folder), "another runner");
    } catch (const OutputError& error) {
      write_error_ = error.what();
      --next_;
      return;
    } catch (const std::runtime_error&) {
      ++held_elsewhere_;
      std::fprintf(stderr, "%s\n", run_folder_busy_line(run_name(i), folder, true).c_str());
      return;
    }
    // an outside runner (--task) that held the lock until now may have finished the run
    if (std::optional<RunSummary> summary =
            finished_summary(state_.plan, folder, state_.scene_texts[i])) {
      state_.summaries[i] = std::move(summary);
      ++done_now_;
      return;
    }
    // an interrupted run goes on from its checkpoint instead of starting again
    std::string why_not;
    const bool resume =
        has_usable_checkpoint(state_.plan.command, folder, state_.scene_texts[i], why_not);
    if (!why_not.empty() && !options_.quiet) {
      std::fprintf(stderr, "%s\n", starts_again_line(run_name(i), why_not).c_str());
    }
    std::string error;
    const int lock_fd = lock->inheritable_fd();
    const pid_t child =
        start_run({state_.plan.command, state_.plan.protocol, state_.plan.scene, folder,
                   run.overrides, options_.checkpoint_every, resume, lock_fd, threads_per_run_},
                  error);
    close(lock_fd);  // the run holds the lock now, and this process lets go of its own
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
    std::optional<RunSummary> summary = read_sweep_run(state_.plan, folder);
    const RunExit end = run_exit(status, summary, state_.scene_texts[i]);
    if (end.unwritten && write_error_.empty()) write_error_ = last_error_of(folder / "log.txt");
    if (end.counts) {
      state_.summaries[i] = std::move(summary);
      ++done_now_;
      if (std::string error = try_write_tables(options_, state_.plan, state_.summaries);
          !error.empty() && write_error_.empty()) {
        write_error_ = std::move(error);
      }
    } else if (signals_.load() == 0 && !time_up_) {
      ++failed_;
    }
    if (!options_.quiet) report(i, end, folder);
  }

  /// "[7/80] point seed 2: porosity=… blocked=yes wall=…s (elapsed 03:10, ≈27:00 left)".
  void report(std::size_t i, const RunExit& end, const std::filesystem::path& folder) const {
    const bool stopped = signals_.load() > 0 || time_up_;
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
    const std::optional<RunSummary>& summary = state_.summaries[i];
    const std::string line =
        end.counts && summary
            ? finished_run_progress(finished, total, run_name(i), *summary, elapsed, eta,
                                    end.unwritten)
            : unfinished_run_progress(finished, total, run_name(i),
                                      unfinished_run_text(stopped, end.fault, end.unwritten),
                                      folder / "log.txt");
    std::fprintf(stderr, "%s\n", line.c_str());
  }

  const SweepOptions& options_;
  SweepState& state_;
  std::chrono::steady_clock::time_point start_;
  const std::atomic<int>& signals_;  ///< stop signals received (sweep.cpp)
  RunningRuns guard_;
  std::size_t next_ = 0;
  std::size_t done_now_ = 0;
  std::size_t failed_ = 0;
  std::size_t left_for_later_ = 0;  ///< not started: not expected to finish within the limit
  std::size_t held_elsewhere_ = 0;  ///< not started: an earlier process still writes its folder
  bool time_up_ = false;
  std::string write_error_;
  int stop_level_sent_ = 0;
  int threads_per_run_ = 0;  ///< kMaxThreadsVariable of each run (0: as the environment says)
};

}  // namespace

int run_pending_runs(const SweepOptions& options, SweepState& state, int jobs,
                     std::chrono::steady_clock::time_point start, const std::atomic<int>& signals) {
  SweepPool pool(options, state, start, signals);
  pool.run(jobs);
  return pool.finish();
}

}  // namespace cdpowder::app
