// time_limit.hpp — running a sweep within a wall-time limit (`cdpowder sweep --time-limit`),
// as on a batch system or a machine kept for a few hours: a run is started only when it is
// expected to finish in the time left, so no computing is lost to runs cut off at the end.
#pragma once

#include "cdpowder/study/sweep_plan.hpp"
#include "cdpowder/study/sweep_results.hpp"

#include <cstddef>
#include <optional>
#include <vector>

namespace cdpowder {

/// A run is expected to take this many times as long as the longest finished run it is
/// compared with (expected_run_seconds): whole runs of one point vary by tens of per cent
/// between seeds and with the load of a shared machine
/// (docs/lab/2026-11-24-what-sweep-wall-times-measure.md).
inline constexpr double kRunTimeMargin = 1.25;

/// How long run `run` of the plan is expected to take [s]: the wall time of the longest
/// finished run of the same point (any seed), or, when that point has none, of the longest
/// finished run of the whole sweep; nullopt when nothing has finished. summaries[i] belongs
/// to plan.runs[i].
std::optional<double> expected_run_seconds(const SweepPlan& plan,
                                           const std::vector<std::optional<RunSummary>>& summaries,
                                           std::size_t run);

/// Whether a run expected to take `expected` seconds (nullopt: not known) may start after
/// `elapsed` seconds of a sweep limited to `limit` seconds: when elapsed + kRunTimeMargin ×
/// expected ≤ limit; a run of unknown length starts whenever time is left.
bool may_start_within(double elapsed, std::optional<double> expected, double limit);

}  // namespace cdpowder
