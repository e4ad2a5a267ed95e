// sweep_messages.cpp — the words a sweep says (sweep_messages.hpp).
#include "cdpowder/study/sweep_messages.hpp"

#include "cdpowder/run/run_messages.hpp"
#include "cdpowder/study/sweep_results.hpp"

#include <fmt/format.h>

namespace cdpowder {

std::string sweep_start_line(std::size_t runs, std::size_t points, std::size_t seeds,
                             std::size_t already_finished, std::size_t reused, int jobs) {
  return fmt::format(
      "sweep: {} runs ({} points × {} seeds), {} already finished ({} of them reused), {} jobs",
      runs, points, seeds, already_finished, reused, jobs);
}

std::string sweep_run_name(std::string_view point, std::int64_t seed) {
  return fmt::format("{} seed {}", point, seed);
}

std::string finished_run_line(std::string_view name, const RunSummary& summary, bool unwritten) {
  return fmt::format("{}: {}{}", name, finished_run_text(summary),
                     unwritten ? kOutputsMissingNote : "");
}

std::string unfinished_run_line(std::string_view name, std::string_view why,
                                const std::filesystem::path& log) {
  return fmt::format("{}: {}, see {}", name, why, log.string());
}

std::string finished_run_progress(std::size_t finished, std::size_t total, std::string_view name,
                                  const RunSummary& summary, double elapsed_seconds,
                                  std::optional<double> remaining_seconds, bool unwritten) {
  const std::string left =
      remaining_seconds ? fmt::format(", ≈{} left", clock_text(*remaining_seconds)) : "";
  return fmt::format("[{}/{}] {}: {} (elapsed {}{}){}", finished, total, name,
                     finished_run_text(summary), clock_text(elapsed_seconds), left,
                     unwritten ? kOutputsMissingNote : "");
}

std::string unfinished_run_progress(std::size_t finished, std::size_t total, std::string_view name,
                                    std::string_view why, const std::filesystem::path& log) {
  return fmt::format("[{}/{}] {}", finished, total, unfinished_run_line(name, why, log));
}

std::string already_finished_line(std::string_view name) {
  return fmt::format("{}: already finished", name);
}

std::string starts_again_line(std::string_view name, std::string_view why_not) {
  return fmt::format("{}: starts again: {}", name, why_not);
}

std::string continues_line(std::string_view name) {
  return fmt::format("{}: continues from its checkpoint", name);
}

std::string run_folder_busy_line(std::string_view name, const std::filesystem::path& folder,
                                 bool left_for_later) {
  return left_for_later
             ? fmt::format(
                   "{}: {} is still being written by an earlier process; "
                   "left for later",
                   name, folder.string())
             : fmt::format("{}: {} is being written by another process", name, folder.string());
}

std::string run_left_to_its_holder_line(std::string_view name,
                                        const std::filesystem::path& folder) {
  return fmt::format("{}: {} is locked by another runner, which runs it; left to it", name,
                     folder.string());
}

std::string run_not_started_line(std::string_view name, std::string_view error) {
  return fmt::format("{}: {}", name, error);
}

std::string nothing_to_reuse_line(const std::filesystem::path& folder) {
  return fmt::format("sweep: --reuse {}: no finished runs under {}", folder.string(),
                     (folder / "runs").string());
}

std::string could_not_reuse_line(const std::filesystem::path& source) {
  return fmt::format("sweep: could not reuse {}; it runs again", source.string());
}

std::string sweep_end_line(const SweepTally& tally, const std::filesystem::path& results_csv) {
  std::string what;
  if (tally.interrupted) {
    what = " (interrupted: run the same command to resume)";
  } else if (tally.failed > 0) {
    what = fmt::format(", {} failed (see their log.txt)", tally.failed);
  }
  const std::size_t left = tally.total - tally.finished - tally.failed;
  if (tally.held_elsewhere > 0) {
    what += fmt::format(
        "; {} run{} still written by an earlier process, left for later (run "
        "the same command again)",
        tally.held_elsewhere, tally.held_elsewhere == 1 ? "" : "s");
  }
  if (!tally.interrupted && tally.time_limit_reached && left > 0) {
    what += fmt::format("; time limit {}: {} run{} left for later (run the same command to resume)",
                        clock_text(*tally.time_limit_reached), left, left == 1 ? "" : "s");
  }
  if (!tally.write_error.empty()) {
    what += fmt::format(
        "; stopped starting runs after a write error ({}): free space and run the same "
        "command to go on; the finished runs are kept{}",
        tally.write_error,
        tally.not_started > 0 ? fmt::format(", {} not started", tally.not_started) : "");
  }
  return fmt::format("sweep: {} of {} runs finished{}; results in {}", tally.finished, tally.total,
                     what, results_csv.string());
}

}  // namespace cdpowder
