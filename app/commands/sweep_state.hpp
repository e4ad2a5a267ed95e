// sweep_state.hpp — what a sweep folder holds against its plan (every run's resolved
// scene, the finished runs' summaries, the runs still to do) and its two tables.
#pragma once

#include "commands/sweep.hpp"

#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/study/sweep_plan.hpp"

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cdpowder::app {

/// What a sweep folder holds against its plan: every run's resolved scene, the finished
/// runs' summaries, and the runs still to do (those another sweep has done, with --reuse,
/// apart).
struct SweepState {
  SweepPlan plan;
  std::vector<std::string> scene_texts;
  std::vector<std::optional<RunSummary>> summaries;
  std::vector<std::size_t> pending;
  std::map<std::size_t, std::filesystem::path> reused;
  /// runs with a summary but missing outputs (run_folder.hpp, missing_run_outputs): pending
  std::map<std::size_t, std::vector<std::string>> incomplete;
};

/// Reads the plan, checks every run's scene (ConfigError, nothing written) and what DIR
/// already holds.
SweepState read_sweep_state(const SweepOptions& options);

/// The summary of the run in `folder` when it has finished for exactly `scene_text` with every
/// output in place (is_reusable, missing_run_outputs); nothing otherwise. Asked again by a
/// runner once it holds the run's lock: another runner may have finished the run meanwhile.
std::optional<RunSummary> finished_summary(const SweepPlan& plan,
                                           const std::filesystem::path& folder,
                                           const std::string& scene_text);

/// results.csv and points.csv of the summaries so far (atomically). Throws OutputError.
void write_tables(const SweepOptions& options, const SweepPlan& plan,
                  const std::vector<std::optional<RunSummary>>& summaries);

/// As write_tables, while runs go on: the failure's message ("cannot write …: No space left
/// on device"), or "" when both tables were written.
std::string try_write_tables(const SweepOptions& options, const SweepPlan& plan,
                             const std::vector<std::optional<RunSummary>>& summaries);

/// A file's whole text (the sweep file, copied into the folder).
std::string read_text(const std::filesystem::path& file);

}  // namespace cdpowder::app
