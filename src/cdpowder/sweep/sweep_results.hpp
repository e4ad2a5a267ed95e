// sweep_results.hpp — the results of a sweep: one record per finished run (read back from
// its summary.json), the table of runs and the aggregate per parameter point.
#pragma once

#include "cdpowder/io/run_summary.hpp"
#include "cdpowder/sweep/sweep_plan.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {

/// The numbers of one run that a sweep tabulates (docs/sweeps.md lists the columns).
struct RunRecord {
  double porosity = 0.0;
  double initial_porosity = 0.0;
  double sigma_zz_over_p = 0.0;              ///< σzz / p
  double sigma_zz_compressive_over_p = 0.0;  ///< σzz+ / p
  double sigma_zz_tensile_over_p = 0.0;      ///< σzz− / p
  double compressive_contacts = 0.0;
  double tensile_contacts = 0.0;
  double coordination_number = 0.0;
  bool blocked = false;
  bool interrupted = false;
  bool failed = false;  ///< a fault stopped the run (summaries before faults existed: false)
  double steps = 0.0;
  double total_sweeps = 0.0;
  double capped_steps = 0.0;
  double mean_overlap = 0.0;      ///< [R]
  double max_overlap = 0.0;       ///< [R]
  double piston_imbalance = 0.0;  ///< |Σ R·e_z − F| / F at the end
  double max_net_force = 0.0;     ///< largest net force on a sphere at the end [F_coh]
  double wall_seconds = 0.0;
  std::string scene_toml;  ///< the run's resolved scene: a restarted sweep compares it
  std::string commit;      ///< the program commit that produced the run
};

/// The numbers of a run's summary that the sweep tabulates.
RunRecord run_record(const RunSummary& summary);

/// "porosity=0.64305 blocked=yes wall=41.2s": a finished run as a sweep's progress lines show it.
std::string finished_run_text(const RunRecord& record);

/// Added to a finished run's line when not all of its outputs were written.
inline constexpr std::string_view kOutputsMissingNote =
    "; not all its outputs were written, see its log.txt";

/// Why a run of a sweep did not finish: "interrupted" (`stopped`), "FAILED (a fault stopped it:
/// unphysical state)", "FAILED (could not write its outputs)" or "FAILED".
std::string unfinished_run_text(bool stopped, bool fault, bool unwritten);

/// Reads the record of a run from its summary.json (read_run_summary, any schema); nullopt
/// when the file is missing or is not a complete summary (a run killed before it wrote one).
std::optional<RunRecord> read_run_record(const std::filesystem::path& summary_json);

/// Whether a run can be reused by a restarted sweep: it finished (neither interrupted nor
/// failed) and ran exactly the scene the sweep asks for now.
bool is_reusable(const std::optional<RunRecord>& record, const std::string& expected_scene_toml);

/// results.csv: a row per run that has a record (records[i] belongs to plan.runs[i]),
/// after the provenance `header` (lines starting with '#').
std::string results_csv(const SweepPlan& plan, const std::vector<std::optional<RunRecord>>& records,
                        const std::string& header);

/// points.csv: a row per point: runs finished, n = runs blocked, and for porosity and the
/// stresses the mean and the standard error of the mean over the blocked runs (empty when
/// n < 2 for the error, n = 0 for the mean).
std::string points_csv(const SweepPlan& plan, const std::vector<std::optional<RunRecord>>& records,
                       const std::string& header);

/// Every finished (not interrupted) run under a sweep folder's `runs/`, by its resolved
/// scene text: where another sweep can reuse a run whose scene is exactly its own
/// (`cdpowder sweep --reuse`). Unreadable summaries are skipped.
std::map<std::string, std::filesystem::path> finished_runs_by_scene(
    const std::filesystem::path& sweep_folder);

}  // namespace cdpowder
