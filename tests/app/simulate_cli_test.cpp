// Tests of app/ (the `cdpowder simulate` command) run as a user would: the program is
// started as a process, its exit status and its output folder are checked.
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "support/cli_process.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kExamples = CDPOWDER_SOURCE_DIR "/examples";

using cdpowder::testing::ProcessResult;
using cdpowder::testing::run_cdpowder;
using cdpowder::testing::slurp;

using SimulateCli = cdpowder::testing::ScratchFolderTest;

// A short run of the example lattice (the quick start compacts it to the end).
const std::string kShort = "--set run.until_blocked=false --set run.duration=2.0 --quiet";

TEST_F(SimulateCli, WritesEveryOutputAndAResultLine) {
  const ProcessResult r = run_cdpowder("simulate " + (kExamples / "lattice/scene.toml").string() +
                                           " --out " + (scratch_ / "out").string() + " " + kShort,
                                       scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("porosity="));
  for (const char* name :
       {"summary.json", "particles.csv", "contacts.csv", "timeseries.csv", "scene.toml"}) {
    EXPECT_TRUE(fs::exists(scratch_ / "out" / name)) << name;
  }
  const auto summary = nlohmann::json::parse(slurp(scratch_ / "out/summary.json"));
  EXPECT_EQ(summary["seed"], 1);
  EXPECT_EQ(summary["spheres"], 216);
  EXPECT_EQ(summary["run"]["steps"], 200);
  EXPECT_EQ(summary["scene"]["run"]["duration"], 2.0);
  // a run that does not block has no static final solve: its forces are those of the last
  // step of the dynamics, and the summary says so
  EXPECT_FALSE(summary["run"]["blocked"].get<bool>());
  EXPECT_TRUE(summary["accuracy"]["final_solve"].is_null());
  EXPECT_FALSE(summary["program"]["version"].get<std::string>().empty());
  // no temporary files are left behind (.run.lock, the run's lock on its folder, stays)
  for (const auto& entry : fs::directory_iterator(scratch_ / "out")) {
    if (entry.path().filename() == ".run.lock") continue;
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
  }
}

// A deposit settling under gravity with no piston runs until the spheres alone are blocked
// (physics.md §9): at rest for a window, then a static solve with every sphere in balance
// against their weight. The deposit of the quick example collapses from E = 0.913.
TEST_F(SimulateCli, ASettlingWithoutAPistonRunsUntilTheSpheresAreBlocked) {
  const ProcessResult r =
      run_cdpowder("simulate " + (kExamples / "quick/scene.toml").string() + " --out " +
                       (scratch_ / "out").string() +
                       " --quiet --set piston.enabled=false --set system.gravity=[0,0,-0.01]"
                       " --set contact.mu_roll=0.0 --set contact.mu_twist=0.0",
                   scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(scratch_ / "out/summary.json"));
  EXPECT_TRUE(summary["run"]["blocked"].get<bool>());
  EXPECT_TRUE(summary["accuracy"]["final_solve"]["converged"].get<bool>());
  // the weight of 100 unit spheres of density 1 under g = 0.01, times force_balance 1e-2
  EXPECT_LT(summary["accuracy"]["max_net_force"].get<double>(), 1e-2 * 100 * 4.18879 * 0.01);
  EXPECT_LT(summary["porosity"].get<double>(), summary["initial_porosity"].get<double>() - 0.1);
  EXPECT_LT(summary["time"].get<double>(), 5000.0);  // ended blocked, not at max_duration
}

// A library user who runs the loop with a RunFolder gets the command line's files: the same
// list, and the same bytes in all but the wall times.
TEST_F(SimulateCli, ALibraryRunWritesTheCommandLinesFiles) {
  const fs::path scene_file = kExamples / "lattice/scene.toml";
  const std::vector<std::string> overrides{"run.until_blocked=false", "run.duration=1.0",
                                           "run.snapshot_every=40"};
  std::string options;
  for (const std::string& o : overrides) options += " --set " + o;
  const ProcessResult r = run_cdpowder("simulate " + scene_file.string() + " --out " +
                                           (scratch_ / "cli").string() + " --quiet" + options,
                                       scratch_);
  ASSERT_EQ(r.status, 0) << r.err;

  const cdpowder::Scene scene =
      cdpowder::read_scene(scene_file, cdpowder::command_line_overrides(overrides));
  cdpowder::World world = cdpowder::make_world(scene);
  cdpowder::StepWorkspace work(scene.step.solver.seed);
  cdpowder::RunState state;
  const double initial_porosity = cdpowder::porosity(world);
  cdpowder::RunFolder files =
      cdpowder::RunFolder::begin(scratch_ / "lib", scene, world, work.contacts, {});
  const cdpowder::RunResult result = cdpowder::run_simulation(
      world, work, scene.step, scene.run, state,
      [&](const cdpowder::World& w, const cdpowder::StepReport& report, double /*fraction*/) {
        files.after_step(w, report, work.contacts);
      });
  files.finish(scene, world, work, state, result, initial_porosity);

  std::vector<std::string> cli_files;
  std::vector<std::string> lib_files;
  for (const auto& e : fs::recursive_directory_iterator(scratch_ / "cli")) {
    if (e.path().filename() != ".run.lock") {
      cli_files.push_back(fs::relative(e.path(), scratch_ / "cli").string());
    }
  }
  for (const auto& e : fs::recursive_directory_iterator(scratch_ / "lib")) {
    lib_files.push_back(fs::relative(e.path(), scratch_ / "lib").string());
  }
  std::sort(cli_files.begin(), cli_files.end());
  std::sort(lib_files.begin(), lib_files.end());
  EXPECT_EQ(lib_files, cli_files);
  EXPECT_GT(cli_files.size(), 10U);  // the outputs and a few snapshots
  for (const std::string& name : cli_files) {
    if (fs::is_directory(scratch_ / "cli" / name) || name == "summary.json") continue;
    EXPECT_EQ(slurp(scratch_ / "lib" / name), slurp(scratch_ / "cli" / name)) << name;
  }
  auto summary = [](const fs::path& file) {
    nlohmann::json j = nlohmann::json::parse(slurp(file));
    j["run"].erase("wall_seconds");
    j["run"].erase("stage_seconds");
    return j;
  };
  EXPECT_EQ(summary(scratch_ / "lib/summary.json"), summary(scratch_ / "cli/summary.json"));
}

TEST_F(SimulateCli, SameSeedGivesIdenticalStateAnotherSeedADifferentOne) {
  const std::string scene = (kExamples / "lattice/scene.toml").string();
  for (const char* run : {"a", "b"}) {
    std::string command = "simulate " + scene;
    command += " --out " + (scratch_ / run).string();
    command += " " + kShort;
    ASSERT_EQ(run_cdpowder(command, scratch_).status, 0);
  }
  ASSERT_EQ(run_cdpowder("simulate " + scene + " --out " + (scratch_ / "c").string() + " " +
                             kShort + " --set solver.seed=2",
                         scratch_)
                .status,
            0);
  EXPECT_EQ(slurp(scratch_ / "a/particles.csv"), slurp(scratch_ / "b/particles.csv"));
  EXPECT_EQ(slurp(scratch_ / "a/contacts.csv"), slurp(scratch_ / "b/contacts.csv"));
  EXPECT_NE(slurp(scratch_ / "a/contacts.csv"), slurp(scratch_ / "c/contacts.csv"));
}

TEST_F(SimulateCli, ParticlesOutputReadsBackAsInput) {
  const std::string scene = (kExamples / "lattice/scene.toml").string();
  ASSERT_EQ(run_cdpowder("simulate " + scene + " --out " + (scratch_ / "a").string() + " " + kShort,
                         scratch_)
                .status,
            0);
  const ProcessResult again = run_cdpowder(
      "simulate " + scene + " --out " + (scratch_ / "b").string() + " " + kShort +
          " --set 'particles.file=\"" + (scratch_ / "a/particles.csv").string() + "\"'",
      scratch_);
  EXPECT_EQ(again.status, 0) << again.err;
}

TEST_F(SimulateCli, BadInputExitsWithTwoNamesTheKeyAndWritesNothing) {
  const ProcessResult r =
      run_cdpowder("simulate " + (kExamples / "lattice/scene.toml").string() + " --out " +
                       (scratch_ / "out").string() + " --set contact.mu_roll=-0.2",
                   scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("contact.mu_roll"));
  EXPECT_THAT(r.err, HasSubstr("-0.2"));
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

TEST_F(SimulateCli, MissingSceneFileExitsWithTwo) {
  const ProcessResult r = run_cdpowder(
      "simulate " + (scratch_ / "nope.toml").string() + " --out " + (scratch_ / "out").string(),
      scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("nope.toml"));
}

TEST_F(SimulateCli, MissingOutOptionExitsWithTwo) {
  EXPECT_EQ(
      run_cdpowder("simulate " + (kExamples / "lattice/scene.toml").string(), scratch_).status, 2);
}

}  // namespace
