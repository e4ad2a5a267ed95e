// sweep_plan_test.cpp — reading sweep files: grids, explicit points, seeds, run folders and
// overrides, the tables built from run records, and every class of mistake.
#include "cdpowder/study/sweep_plan.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/study/sweep_results.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace cdpowder {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

SweepPlan plan_of(const std::string& text, const std::vector<std::string>& extra = {}) {
  return read_sweep_plan_text(text, "sweep.toml", "/base", extra);
}

/// The overrides' texts, as the run's command line passes them.
std::vector<std::string> texts(const std::vector<SceneOverride>& overrides) {
  std::vector<std::string> result;
  result.reserve(overrides.size());
  for (const SceneOverride& o : overrides) result.push_back(o.text);
  return result;
}

/// Where each override comes from, for the messages of the scene reader.
std::vector<std::string> origins(const std::vector<SceneOverride>& overrides) {
  std::vector<std::string> result;
  result.reserve(overrides.size());
  for (const SceneOverride& o : overrides) result.push_back(o.origin);
  return result;
}

/// The formatted issues of a plan that must be refused.
std::string errors_of(const std::string& text) {
  try {
    plan_of(text);
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return "";
}

TEST(SweepPlan, SaysAFolderIsNotASweepFile) {
  try {
    (void)read_sweep_plan(std::filesystem::temp_directory_path());
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1U);
    EXPECT_THAT(error.what(), HasSubstr("is a folder; expected a sweep file"));
  }
}

// `command`: each run is a compaction (the default), a simulation of the scene or a Python
// protocol
TEST(SweepPlan, TheCommandIsCompactUnlessTheFileSaysSimulate) {
  EXPECT_EQ(plan_of("scene = \"s.toml\"\n").command, SweepCommand::Compact);
  EXPECT_EQ(plan_of("scene = \"s.toml\"\ncommand = \"simulate\"\n").command,
            SweepCommand::Simulate);
  EXPECT_STREQ(command_name(SweepCommand::Simulate), "simulate");
  EXPECT_THAT(errors_of("scene = \"s.toml\"\ncommand = \"deposit\"\n"),
              HasSubstr("command: got \"deposit\", expected \"compact\", \"simulate\" or "
                        "\"python\""));
}

// command = "python" runs `protocol = "FILE:FUNCTION"`, the file relative to the sweep file
TEST(SweepPlan, APythonProtocolNamesItsFileAndFunction) {
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "cdpowder_sweep_protocol_test";
  std::filesystem::create_directories(scratch);
  std::ofstream(scratch / "steps.py") << "def run(scene, out):\n    pass\n";
  const SweepPlan plan = read_sweep_plan_text(
      "scene = \"s.toml\"\ncommand = \"python\"\nprotocol = \"steps.py:run\"\n", "sweep.toml",
      scratch);
  EXPECT_EQ(plan.command, SweepCommand::Python);
  EXPECT_EQ(plan.protocol.file, scratch / "steps.py");
  EXPECT_EQ(plan.protocol.function, "run");
  EXPECT_EQ(plan.protocol.name, "steps.py:run");
  EXPECT_STREQ(command_name(SweepCommand::Python), "python");
  std::filesystem::remove_all(scratch);

  EXPECT_THAT(errors_of("scene = \"s.toml\"\ncommand = \"python\"\n"),
              HasSubstr("protocol: missing: command = \"python\" needs protocol = "
                        "\"FILE.py:FUNCTION\""));
  EXPECT_THAT(errors_of("scene = \"s.toml\"\ncommand = \"python\"\nprotocol = \"steps.py\"\n"),
              HasSubstr("protocol: got \"steps.py\", expected \"FILE.py:FUNCTION\""));
  EXPECT_THAT(errors_of("scene = \"s.toml\"\ncommand = \"python\"\nprotocol = \"steps.py:2run\"\n"),
              HasSubstr("expected \"FILE.py:FUNCTION\""));
  EXPECT_THAT(errors_of("scene = \"s.toml\"\ncommand = \"python\"\nprotocol = \"gone.py:run\"\n"),
              HasSubstr("/base/gone.py: no such file"));
  EXPECT_THAT(errors_of("scene = \"s.toml\"\nprotocol = \"steps.py:run\"\n"),
              HasSubstr("protocol: is read only with command = \"python\""));
}

// Provenance records a file as the user named it: a sweep file given relative to the working
// folder gives a base scene relative to it too, never this machine's absolute path (the
// sweep's tables and every run's outputs record plan.scene).
TEST(SweepPlan, TheBaseSceneIsRelativeToTheSweepFileAsNamed) {
  const std::filesystem::path before = std::filesystem::current_path();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "cdpowder_sweep_plan_relative";
  std::filesystem::remove_all(scratch);
  std::filesystem::create_directories(scratch / "sub");
  { std::ofstream(scratch / "sub/sweep.toml") << "scene = \"scene.toml\"\nseeds = 2\n"; }
  SweepPlan plan;
  try {
    std::filesystem::current_path(scratch);
    plan = read_sweep_plan("sub/sweep.toml");
  } catch (...) {
    std::filesystem::current_path(before);  // the other tests run in the folder they expect
    throw;
  }
  std::filesystem::current_path(before);
  std::filesystem::remove_all(scratch);
  EXPECT_EQ(plan.scene, std::filesystem::path("sub/scene.toml"));
  EXPECT_EQ(plan.source, std::filesystem::path("sub/sweep.toml"));
}

TEST(SweepPlan, GridIsTheCartesianProductWithTheLastKeyFastest) {
  const SweepPlan plan = plan_of(R"(
scene = "scene.toml"
seeds = 2
[grid.contact]
mu_roll = [0.0, 1.0]
mu_twist = [0.0, 0.5, 1.0]
)");
  EXPECT_EQ(plan.scene, std::filesystem::path("/base/scene.toml"));
  EXPECT_THAT(plan.parameter_keys, ElementsAre("contact.mu_roll", "contact.mu_twist"));
  ASSERT_EQ(plan.points.size(), 6U);
  EXPECT_EQ(plan.points[0].name, "contact.mu_roll=0.0,contact.mu_twist=0.0");
  EXPECT_EQ(plan.points[1].name, "contact.mu_roll=0.0,contact.mu_twist=0.5");
  EXPECT_EQ(plan.points[5].name, "contact.mu_roll=1.0,contact.mu_twist=1.0");
  ASSERT_EQ(plan.runs.size(), 12U);
  EXPECT_EQ(plan.runs[3].point, 1U);
  EXPECT_EQ(plan.runs[3].seed, 2);
  EXPECT_EQ(plan.runs[3].folder.generic_string(),
            "runs/contact.mu_roll=0.0,contact.mu_twist=0.5/seed_2");
  EXPECT_THAT(texts(plan.runs[3].overrides),
              ElementsAre("contact.mu_roll=0.0", "contact.mu_twist=0.5", "deposition.seed=2",
                          "solver.seed=2"));
}

TEST(SweepPlan, RunsGoSeedBySeedSoAnEarlyStopCoversEveryPoint) {
  const SweepPlan plan = plan_of(R"(
scene = "scene.toml"
seeds = [4, 7, 9]
[grid.contact]
mu_roll = [0.0, 0.5]
)");
  ASSERT_EQ(plan.runs.size(), 6U);
  // all six, and a resumed sweep's pending subset (runs 0 and 4 already finished)
  std::vector<std::size_t> all = {0, 1, 2, 3, 4, 5};
  order_seed_by_seed(plan, all);
  std::vector<std::pair<std::size_t, std::int64_t>> point_and_seed;
  point_and_seed.reserve(all.size());
  for (const std::size_t i : all)
    point_and_seed.emplace_back(plan.runs[i].point, plan.runs[i].seed);
  EXPECT_THAT(point_and_seed, ElementsAre(std::pair<std::size_t, std::int64_t>(0, 4),
                                          std::pair<std::size_t, std::int64_t>(1, 4),
                                          std::pair<std::size_t, std::int64_t>(0, 7),
                                          std::pair<std::size_t, std::int64_t>(1, 7),
                                          std::pair<std::size_t, std::int64_t>(0, 9),
                                          std::pair<std::size_t, std::int64_t>(1, 9)));
  std::vector<std::size_t> pending = {1, 2, 3, 5};
  order_seed_by_seed(plan, pending);
  EXPECT_THAT(pending, ElementsAre(3, 1, 2, 5));  // (point, seed): (1,4) (0,7) (0,9) (1,9)
}

// points_csv: a table of points beside the sweep file, one a row, as yade-batch's
TEST(SweepPlan, PointsMayComeFromACsvTable) {
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "cdpowder_sweep_plan_csv";
  std::filesystem::remove_all(scratch);
  std::filesystem::create_directories(scratch);
  {
    std::ofstream(scratch / "points.csv") << "# pressure and rule\n"
                                          << "piston.pressure, contact.cohesion_rule\n"
                                          << "0.001,history\n0.004,\n\n1e-2,\"graph\"\n";
  }
  const SweepPlan plan = read_sweep_plan_text("scene = \"s.toml\"\npoints_csv = \"points.csv\"\n",
                                              "sweep.toml", scratch);
  ASSERT_EQ(plan.points.size(), 3U);
  EXPECT_EQ(plan.parameter_keys,
            (std::vector<std::string>{"piston.pressure", "contact.cohesion_rule"}));
  EXPECT_EQ(plan.points[0].name, "piston.pressure=0.001,contact.cohesion_rule=history");
  EXPECT_EQ(plan.points[1].settings.size(), 1U);  // an empty cell keeps the scene's value
  EXPECT_EQ(plan.points[2].settings[0].value, "1e-2");
  EXPECT_EQ(plan.points[2].settings[1].value, "\"graph\"");
  EXPECT_EQ(plan.points[0].settings[0].origin, "points.csv:3");
  { std::ofstream(scratch / "bad.csv") << "piston.pressure\n0.001,2\n"; }
  try {
    (void)read_sweep_plan_text("scene = \"s.toml\"\npoints_csv = \"bad.csv\"\n", "sweep.toml",
                               scratch);
    ADD_FAILURE() << "a row of two cells under one key was accepted";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("bad.csv:2: got 2 cells, expected 1"));
  }
  std::filesystem::remove_all(scratch);
}

TEST(SweepPlan, ExplicitPointsFixedOverridesAndSeedListsCombine) {
  const SweepPlan plan = plan_of(R"(
scene = "/abs/scene.toml"
seeds = [7, 3]
seed_keys = ["solver.seed"]
set = ["solver.tolerance=1e-4"]
[[points]]
"contact.mu_roll" = 0.3
"contact.mu_twist" = 0
[[points]]
contact.cohesion_rule = "history"
)",
                                 {"run.max_duration=5"});
  EXPECT_EQ(plan.scene, std::filesystem::path("/abs/scene.toml"));
  ASSERT_EQ(plan.points.size(), 2U);
  EXPECT_EQ(plan.points[0].name, "contact.mu_roll=0.3,contact.mu_twist=0");
  EXPECT_EQ(plan.points[1].name, "contact.cohesion_rule=history");
  ASSERT_EQ(plan.runs.size(), 4U);
  EXPECT_THAT(texts(plan.runs[2].overrides),
              ElementsAre("solver.tolerance=1e-4", "run.max_duration=5",
                          "contact.cohesion_rule=\"history\"", "solver.seed=7"));
  // a mistake in one of them is reported where it was written (the scene reader's messages)
  EXPECT_THAT(origins(plan.runs[2].overrides),
              ElementsAre("sweep.toml:5:8", "--set", "sweep.toml:10:25", "sweep.toml:3:9"));
  EXPECT_THAT(origins(plan.runs[0].overrides),
              ElementsAre("sweep.toml:5:8", "--set", "sweep.toml:7:21", "sweep.toml:8:22",
                          "sweep.toml:3:9"));
}

TEST(SweepPlan, NoParametersMeansTheBaseSceneOverTheSeeds) {
  const SweepPlan plan = plan_of("scene = \"s.toml\"\nseeds = 3\n");
  ASSERT_EQ(plan.points.size(), 1U);
  EXPECT_EQ(plan.points[0].name, "base");
  EXPECT_EQ(plan.runs.size(), 3U);
}

TEST(SweepPlan, APointInTheGridAndListedAgainRunsOnce) {
  const SweepPlan plan = plan_of(R"(
scene = "s.toml"
[grid]
"contact.mu_roll" = [0.0, 1.0]
[[points]]
"contact.mu_roll" = 1.0
)");
  EXPECT_EQ(plan.points.size(), 2U);
}

TEST(SweepPlan, MistakesNameTheKeyAndWhatIsAllowed) {
  EXPECT_THAT(errors_of("seeds = 2\n"), HasSubstr("scene: missing"));
  EXPECT_THAT(errors_of("scene = \"s\"\nseed = 2\n"), HasSubstr("did you mean 'seeds'?"));
  EXPECT_THAT(errors_of("scene = \"s\"\nseeds = 0\n"), HasSubstr("expected a count in [1"));
  EXPECT_THAT(errors_of("scene = \"s\"\nseeds = [1, 1]\n"), HasSubstr("listed twice"));
  EXPECT_THAT(errors_of("scene = \"s\"\n[grid]\n\"contact.mu\" = []\n"),
              HasSubstr("grid.contact.mu: expected a non-empty list"));
  EXPECT_THAT(errors_of("scene = \"s\"\n[grid]\n\"contact.mu\" = [0.1, 0.1]\n"),
              HasSubstr("value 0.1 is listed twice"));
  EXPECT_THAT(errors_of("scene = \"s\"\n[grid]\n\"contact.mu\" = [[1]]\n"),
              HasSubstr("expected a number, a boolean or a string"));
  EXPECT_THAT(errors_of("scene = \"s\"\n[grid]\n\"solver.seed\" = [1, 2]\n"),
              HasSubstr("is a seed key"));
  EXPECT_THAT(errors_of("scene = \"s\"\nset = \"a=1\"\n"), HasSubstr("set: expected a list"));
  EXPECT_THAT(errors_of("scene = [\n"), HasSubstr("TOML syntax error"));
  EXPECT_THAT(errors_of("scene = \"s\"\n[grid]\n\"contact.mu\" = [0.1]\n"
                        "[grid.contact]\nmu = [0.2]\n"),
              HasSubstr("grid.contact.mu: is given twice"));
}

RunSummary summary(double porosity, bool blocked) {
  RunSummary r;
  r.porosity = porosity;
  r.run.blocked = blocked;
  r.stress.sigma_zz_over_pressure = 1.0;
  r.program.commit = "abc";
  return r;
}

TEST(SweepResults, PointsAverageTheBlockedRunsWithTheStandardError) {
  const SweepPlan plan = plan_of("scene = \"s\"\nseeds = 4\n[grid]\n\"contact.mu\" = [0.1, 0.2]\n");
  std::vector<std::optional<RunSummary>> summaries(plan.runs.size());
  summaries[0] = summary(0.5, true);
  summaries[1] = summary(0.7, true);
  summaries[2] = summary(0.9, false);  // finished, not blocked: listed, not averaged
  summaries[4] = summary(0.4, true);
  const std::string points = points_csv(plan, summaries, "# h\n");
  // point 0: runs 3, n 2, mean 0.6, sem = sd/√n = 0.1414…/√2 = 0.1
  EXPECT_THAT(points, HasSubstr("contact.mu=0.1,0.1,3,2,0.6,0.1,1,0,"));
  // point 1: one blocked run: a mean, no error
  EXPECT_THAT(points, HasSubstr("contact.mu=0.2,0.2,1,1,0.4,,1,,"));
  const std::string runs = results_csv(plan, summaries, "# h\n");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 1 + 4);  // header lines + 4 rows
  EXPECT_THAT(runs, HasSubstr("contact.mu=0.1,0.1,3,0.9,"));
}

TEST(SweepResults, ARunIsReusedOnlyWhenFinishedForTheSameScene) {
  RunSummary r = summary(0.5, true);
  r.scene_toml = "a";
  EXPECT_TRUE(is_reusable(r, "a"));
  EXPECT_FALSE(is_reusable(r, "b"));
  r.run.failed = true;
  EXPECT_FALSE(is_reusable(r, "a"));
  r.run.failed = false;
  r.run.interrupted = true;
  EXPECT_FALSE(is_reusable(r, "a"));
  EXPECT_FALSE(is_reusable(std::nullopt, "a"));
}

}  // namespace
}  // namespace cdpowder
