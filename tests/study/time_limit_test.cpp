// time_limit_test.cpp — a sweep within a wall-time limit: the expected length of a run from
// the finished ones, and when a run may start (durations: tests/app/duration_test.cpp).
#include "cdpowder/study/time_limit.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace cdpowder {
namespace {

/// A plan of `points` points × 2 seeds (runs point-major) with summaries of the given wall
/// times (nullopt: not finished).
struct PlanWithRecords {
  SweepPlan plan;
  std::vector<std::optional<RunSummary>> records;
};

PlanWithRecords plan_with(std::size_t points, const std::vector<std::optional<double>>& seconds) {
  PlanWithRecords p;
  p.plan.points.resize(points);
  for (std::size_t point = 0; point < points; ++point) {
    for (std::int64_t seed = 1; seed <= 2; ++seed) {
      SweepRun run;
      run.point = point;
      run.seed = seed;
      p.plan.runs.push_back(run);
    }
  }
  for (const std::optional<double>& s : seconds) {
    if (!s) {
      p.records.emplace_back();
      continue;
    }
    RunSummary summary;
    summary.run.wall_seconds = *s;
    p.records.emplace_back(summary);
  }
  return p;
}

TEST(ExpectedRunSeconds, IsTheLongestFinishedRunOfThePointElseOfTheSweep) {
  // point 0: seed 1 took 100 s; point 1: seeds 1 and 2 took 300 and 200 s; point 2: none
  const PlanWithRecords p =
      plan_with(3, {100.0, std::nullopt, 300.0, 200.0, std::nullopt, std::nullopt});
  EXPECT_EQ(expected_run_seconds(p.plan, p.records, 1), 100.0);  // its point's, not the sweep's
  EXPECT_EQ(expected_run_seconds(p.plan, p.records, 3), 300.0);
  EXPECT_EQ(expected_run_seconds(p.plan, p.records, 4), 300.0);  // nothing of point 2: the sweep
  const PlanWithRecords none =
      plan_with(2, {std::nullopt, std::nullopt, std::nullopt, std::nullopt});
  EXPECT_EQ(expected_run_seconds(none.plan, none.records, 0), std::nullopt);
}

TEST(MayStartWithin, LeavesRoomForTheExpectedRunWithAMargin) {
  // 1000 s limit, a 400 s run: 1.25 × 400 = 500 s must fit in what is left
  EXPECT_TRUE(may_start_within(500.0, 400.0, 1000.0));
  EXPECT_FALSE(may_start_within(500.1, 400.0, 1000.0));
  EXPECT_FALSE(may_start_within(600.0, 400.0, 1000.0));
  // a run of unknown length starts while time is left, and nothing starts past the limit
  EXPECT_TRUE(may_start_within(999.0, std::nullopt, 1000.0));
  EXPECT_FALSE(may_start_within(1000.0, std::nullopt, 1000.0));
  EXPECT_FALSE(may_start_within(1000.0, 0.0, 1000.0));
}

}  // namespace
}  // namespace cdpowder
