// sweep_results.hpp — the results of a sweep: each finished run's summary (read back from its
// summary.json by the one reader, run/run_summary.hpp), the table of runs and the aggregate per
// parameter point.
#pragma once

#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/study/sweep_plan.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {

/// "porosity=0.64305 blocked=yes wall=41.2s": a finished run as a sweep's progress lines show it.
std::string finished_run_text(const RunSummary& summary);

/// Added to a finished run's line when not all of its outputs were written.
inline constexpr std::string_view kOutputsMissingNote =
    "; not all its outputs were written, see its log.txt";

/// Why a run of a sweep did not finish: "interrupted" (`stopped`), "FAILED (a fault stopped it:
/// unphysical state)", "FAILED (could not write its outputs)" or "FAILED".
std::string unfinished_run_text(bool stopped, bool fault, bool unwritten);

/// Whether a run can be reused by a restarted sweep: it finished (neither interrupted nor
/// failed) and ran exactly the scene the sweep asks for now.
bool is_reusable(const std::optional<RunSummary>& summary, const std::string& expected_scene_toml);

/// results.csv: a row per run that has a summary (summaries[i] belongs to plan.runs[i]),
/// after the provenance `header` (lines starting with '#').
std::string results_csv(const SweepPlan& plan,
                        const std::vector<std::optional<RunSummary>>& summaries,
                        const std::string& header);

/// points.csv: a row per point: runs finished, n = runs blocked, and for porosity and the
/// stresses the mean and the standard error of the mean over the blocked runs (empty when
/// n < 2 for the error, n = 0 for the mean).
std::string points_csv(const SweepPlan& plan,
                       const std::vector<std::optional<RunSummary>>& summaries,
                       const std::string& header);

/// Every finished (not interrupted) run under a sweep folder's `runs/`, by its resolved
/// scene text: where another sweep can reuse a run whose scene is exactly its own
/// (`cdpowder sweep --reuse`). Unreadable summaries are skipped.
std::map<std::string, std::filesystem::path> finished_runs_by_scene(
    const std::filesystem::path& sweep_folder);

}  // namespace cdpowder
