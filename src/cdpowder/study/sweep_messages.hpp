// sweep_messages.hpp — the words a sweep says: the line it starts with, a line per run as runs
// end, the notes on runs it reuses, continues or leaves, and its last line. The command line
// prints them; they are here, beside the run's own words (run/run_messages.hpp), so that every
// message of the program is text of the library, tested where it is made (the library itself
// never prints).
#pragma once

#include "cdpowder/run/run_summary.hpp"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace cdpowder {

/// "sweep: 80 runs (8 points × 10 seeds), 24 already finished (24 of them reused), 2 jobs".
std::string sweep_start_line(std::size_t runs, std::size_t points, std::size_t seeds,
                             std::size_t already_finished, std::size_t reused, int jobs);

/// "POINT seed S": a run as the sweep's lines name it.
std::string sweep_run_name(std::string_view point, std::int64_t seed);

/// "NAME: porosity=… blocked=yes wall=…s" (and kOutputsMissingNote when not all its outputs
/// were written).
std::string finished_run_line(std::string_view name, const RunSummary& summary, bool unwritten);

/// "NAME: interrupted, see FOLDER/log.txt": a run that did not finish (unfinished_run_text).
std::string unfinished_run_line(std::string_view name, std::string_view why,
                                const std::filesystem::path& log);

/// "[7/80] " before a run's line as a sweep of `total` runs reports its `finished`-th; a
/// finished run's line ends with " (elapsed 03:10, ≈27:00 left)" before any note:
/// "[7/80] NAME: porosity=… wall=…s (elapsed 03:10, ≈27:00 left)".
std::string finished_run_progress(std::size_t finished, std::size_t total, std::string_view name,
                                  const RunSummary& summary, double elapsed_seconds,
                                  std::optional<double> remaining_seconds, bool unwritten);

/// "[7/80] NAME: FAILED, see FOLDER/log.txt".
std::string unfinished_run_progress(std::size_t finished, std::size_t total, std::string_view name,
                                    std::string_view why, const std::filesystem::path& log);

/// "NAME: already finished" (`--task` on a run that is done).
std::string already_finished_line(std::string_view name);

/// "NAME: starts again: WHY": an unfinished run whose checkpoint cannot be continued.
std::string starts_again_line(std::string_view name, std::string_view why_not);

/// "NAME: continues from its checkpoint".
std::string continues_line(std::string_view name);

/// "NAME: FOLDER is being written by another process" (`--task`), or, when the sweep itself
/// leaves the run to its next start, "… is still being written by an earlier process; left
/// for later".
std::string run_folder_busy_line(std::string_view name, const std::filesystem::path& folder,
                                 bool left_for_later);

/// --task on a run whose folder lock another runner holds: the run is that runner's, and this
/// one ends with 0 (both were started on it at once, as a requeued array job can be).
std::string run_left_to_its_holder_line(std::string_view name, const std::filesystem::path& folder);

/// "NAME: ERROR": a run that could not be started.
std::string run_not_started_line(std::string_view name, std::string_view error);

/// "sweep: --reuse DIR: no finished runs under DIR/runs".
std::string nothing_to_reuse_line(const std::filesystem::path& folder);

/// "sweep: could not reuse SUMMARY; it runs again".
std::string could_not_reuse_line(const std::filesystem::path& source);

/// What a sweep's last line reports.
struct SweepTally {
  std::size_t total = 0;     ///< runs of the plan
  std::size_t finished = 0;  ///< done, now or before
  std::size_t failed = 0;
  std::size_t held_elsewhere = 0;  ///< not started: an earlier process still writes the folder
  std::size_t not_started = 0;     ///< not started after a write error
  bool interrupted = false;        ///< stopped by a signal
  /// the --time-limit [s] when it left runs for later (runs expected to end after it, or
  /// stopped at it)
  std::optional<double> time_limit_reached;
  std::string write_error;  ///< the tables or a run's outputs could not be written
};

/// "sweep: 78 of 80 runs finished, 2 failed (see their log.txt); results in DIR/results.csv",
/// with each reason the tally holds.
std::string sweep_end_line(const SweepTally& tally, const std::filesystem::path& results_csv);

}  // namespace cdpowder
