// time_limit.cpp — see time_limit.hpp.
#include "cdpowder/study/time_limit.hpp"

#include <algorithm>

namespace cdpowder {

std::optional<double> expected_run_seconds(const SweepPlan& plan,
                                           const std::vector<std::optional<RunSummary>>& summaries,
                                           std::size_t run) {
  std::optional<double> same_point;
  std::optional<double> any;
  for (std::size_t i = 0; i < summaries.size() && i < plan.runs.size(); ++i) {
    const std::optional<RunSummary>& summary = summaries[i];
    if (!summary) continue;
    const double seconds = summary->run.wall_seconds;
    any = std::max(any.value_or(seconds), seconds);
    if (plan.runs[i].point == plan.runs[run].point) {
      same_point = std::max(same_point.value_or(seconds), seconds);
    }
  }
  return same_point ? same_point : any;
}

bool may_start_within(double elapsed, std::optional<double> expected, double limit) {
  if (elapsed >= limit) return false;
  return !expected || elapsed + kRunTimeMargin * *expected <= limit;
}

}  // namespace cdpowder
