// The words of a run (run/run_messages.hpp) and of a sweep's runs (study/sweep_results.hpp),
// which the command line prints and a library user reads: what each says, for each ending.
#include "cdpowder/run/run_messages.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "cdpowder/study/sweep_messages.hpp"
#include "cdpowder/study/sweep_results.hpp"
#include "cdpowder/version.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace cdpowder {
namespace {

Scene quick_scene() {
  SceneReadOptions options;
  options.compaction = true;
  return read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml", {},
                    options);
}

/// A fresh empty folder under the system's temporary folder, removed at the end.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }

  ~TemporaryFolder() { std::filesystem::remove_all(path_); }

  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  TemporaryFolder(TemporaryFolder&&) = delete;
  TemporaryFolder& operator=(TemporaryFolder&&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

TEST(RunMessages, TheAnnouncementSaysWhatRanOnOneLine) {
  const Scene scene = quick_scene();
  const std::string line = run_announcement("compact a\nb.toml", scene, "runs/x\ny", 100);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(line.rfind(std::string("cdpowder ") + kVersion + " (commit " + kGitCommit + "): ", 0),
            0U);
  EXPECT_NE(line.find("100 spheres, seed 1, deposition seed"), std::string::npos) << line;
}

TEST(RunMessages, TheResultLineGivesTheStressOverThePressureAndTheCounts) {
  const Scene scene = quick_scene();
  const World world = make_world(scene);
  RunResult result;
  result.steps = 4;
  result.total_passes = 10;
  result.blocked = true;
  result.wall_seconds = 1.25;
  const std::string line = result_line(scene, world, Contacts{}, result);
  EXPECT_EQ(line.rfind("porosity=0.", 0), 0U) << line;
  // no contacts: no stress; the quick example pushes with a pressure
  EXPECT_NE(line.find(" sigma_zz/p=0.0000 sigma_zz+/p=0.0000 sigma_zz-/p=0.0000"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find(" blocked=yes steps=4 passes/step=2.5 wall=1.25s"), std::string::npos)
      << line;
}

TEST(RunMessages, EachEarlyEndingSaysWhatToDo) {
  const Scene scene = quick_scene();
  World world = make_world(scene);
  world.time = 12.5;
  RunResult result;
  result.blocked = true;
  EXPECT_FALSE(run_end_notice(scene, world, result, "out").has_value());

  result.blocked = false;  // the quick example runs until blocked
  auto notice = run_end_notice(scene, world, result, "out");
  ASSERT_TRUE(notice.has_value());
  EXPECT_EQ(notice->ending, RunEnding::NotBlocked);
  EXPECT_NE(notice->message.find("did not block within run.max_duration"), std::string::npos);
  EXPECT_NE(notice->message.find("(t = 12.5 t0)"), std::string::npos) << notice->message;

  result.interrupted = true;
  result.steps = 7;
  notice = run_end_notice(scene, world, result, "out");
  ASSERT_TRUE(notice.has_value());
  EXPECT_EQ(notice->ending, RunEnding::Interrupted);
  EXPECT_EQ(notice->message,
            "interrupted at step 7 (t = 12.5 t0); cdpowder resume out continues it");

  RunFault fault;
  fault.message = "a sphere left the cell";
  result.fault = fault;
  notice = run_end_notice(scene, world, result, "out");
  ASSERT_TRUE(notice.has_value());
  EXPECT_EQ(notice->ending, RunEnding::Failed);
  EXPECT_EQ(notice->message,
            "the run failed: a sphere left the cell; outputs and failed_state.cdps in out");
}

TEST(RunMessages, OnlyACheckpointOfAnotherBuildIsWarnedAbout) {
  EXPECT_EQ(other_build_warning("c.cdps", kVersion, kGitCommit), "");
  const std::string warning = other_build_warning("c.cdps", "0.0.1", "abc");
  EXPECT_EQ(
      warning.rfind("c.cdps was written by cdpowder 0.0.1 (commit abc), this is cdpowder ", 0), 0U)
      << warning;
  EXPECT_NE(warning.find("will not be bit-identical"), std::string::npos);
}

TEST(RunMessages, AFolderWithoutACheckpointOrItsStartingPackingCannotBeResumed) {
  const TemporaryFolder folder("cdpowder_run_messages_test");
  try {
    require_checkpoint(folder.path());
    ADD_FAILURE() << "no checkpoint, no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("no checkpoint.cdps to continue from"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find("this run has finished"), std::string::npos);
  }
  std::ofstream(folder.path() / "summary.json") << "{}";
  try {
    require_checkpoint(folder.path());
    ADD_FAILURE() << "no checkpoint, no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(", and this run has finished"), std::string::npos);
  }
  EXPECT_THROW(require_initial_particles(folder.path()), ConfigError);
  std::ofstream(checkpoint_path(folder.path())) << "x";
  std::ofstream(folder.path() / "initial_particles.csv") << "x";
  EXPECT_NO_THROW(require_checkpoint(folder.path()));
  EXPECT_NO_THROW(require_initial_particles(folder.path()));
}

TEST(SweepMessages, ARunsLineSaysHowItEnded) {
  RunSummary summary;
  summary.porosity = 0.643046;
  summary.run.blocked = true;
  summary.run.wall_seconds = 41.23;
  EXPECT_EQ(finished_run_text(summary), "porosity=0.64305 blocked=yes wall=41.2s");
  EXPECT_EQ(unfinished_run_text(true, true, true), "interrupted");
  EXPECT_EQ(unfinished_run_text(false, true, true),
            "FAILED (a fault stopped it: unphysical state)");
  EXPECT_EQ(unfinished_run_text(false, false, true), "FAILED (could not write its outputs)");
  EXPECT_EQ(unfinished_run_text(false, false, false), "FAILED");
}

TEST(RunMessages, ADepositsLineHasItsPorosityCountHeightAndTime) {
  World world;
  world.box = PeriodicBox{4.0, 4.0};
  world.bodies.add_sphere(Vec3(1.0, 1.0, 1.0), 1.0, 1.0);
  // one sphere of volume 4π/3 under height 2 in a 4 × 4 cell: E = 1 − (4π/3)/32
  EXPECT_EQ(deposit_line(world, 0.0125), "porosity=0.86910 spheres=1 height=2.0000 wall=0.013s");
}

TEST(RunMessages, ClockTextReadsAsMinutesThenHours) {
  EXPECT_EQ(clock_text(0.4), "00:00");
  EXPECT_EQ(clock_text(59.5), "01:00");
  EXPECT_EQ(clock_text(3599.4), "59:59");
  EXPECT_EQ(clock_text(3600.0), "1:00:00");
  EXPECT_EQ(clock_text(36000.0 + 61.0), "10:01:01");
}

TEST(RunMessages, TheProgressTextShowsThePistonAndAnUpperBoundOfTheTimeLeft) {
  const Scene scene =
      read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml", {});
  World world = make_world(scene);
  world.time = 12.345;
  EXPECT_EQ(progress_text(world, 120, 35.94, 30.0, 0.25).substr(0, 12), "t=12.35 Z_P=");
  EXPECT_NE(progress_text(world, 120, 35.94, 30.0, 0.25)
                .find(" passes/step=35.9 contacts=120 elapsed 00:30 remaining <= 01:30"),
            std::string::npos);
  EXPECT_NE(progress_text(world, 120, 1.0, 30.0, 0.0).find("remaining <= ?"), std::string::npos);
  world.walls.piston.enabled = false;
  EXPECT_EQ(progress_text(world, 7, 2.0, 0.0, 0.5),
            "t=12.35 passes/step=2.0 contacts=7 elapsed 00:00 remaining <= 00:00");
}

TEST(SweepMessages, ProgressLinesCountTheRunsAndTellTheTimeLeft) {
  RunSummary summary;
  summary.porosity = 0.643046;
  summary.run.blocked = true;
  summary.run.wall_seconds = 41.23;
  const std::string name = sweep_run_name("contact.mu_roll=0.0", 2);
  EXPECT_EQ(name, "contact.mu_roll=0.0 seed 2");
  EXPECT_EQ(finished_run_progress(7, 80, name, summary, 190.0, 1620.0, false),
            "[7/80] contact.mu_roll=0.0 seed 2: porosity=0.64305 blocked=yes wall=41.2s "
            "(elapsed 03:10, ≈27:00 left)");
  EXPECT_EQ(finished_run_progress(7, 80, name, summary, 190.0, std::nullopt, true),
            "[7/80] contact.mu_roll=0.0 seed 2: porosity=0.64305 blocked=yes wall=41.2s "
            "(elapsed 03:10)" +
                std::string(kOutputsMissingNote));
  EXPECT_EQ(unfinished_run_progress(8, 80, name, "FAILED", "runs/x/log.txt"),
            "[8/80] contact.mu_roll=0.0 seed 2: FAILED, see runs/x/log.txt");
  EXPECT_EQ(finished_run_line(name, summary, false),
            "contact.mu_roll=0.0 seed 2: porosity=0.64305 blocked=yes wall=41.2s");
  EXPECT_EQ(
      sweep_start_line(80, 8, 10, 24, 24, 2),
      "sweep: 80 runs (8 points × 10 seeds), 24 already finished (24 of them reused), 2 jobs");
  EXPECT_EQ(run_folder_busy_line(name, "runs/x", true),
            "contact.mu_roll=0.0 seed 2: runs/x is still being written by an earlier process; "
            "left for later");
  EXPECT_EQ(nothing_to_reuse_line("old"), "sweep: --reuse old: no finished runs under old/runs");
}

TEST(SweepMessages, TheLastLineGivesEveryReasonARunDidNotFinish) {
  SweepTally tally;
  tally.total = 80;
  tally.finished = 80;
  EXPECT_EQ(sweep_end_line(tally, "out/results.csv"),
            "sweep: 80 of 80 runs finished; results in out/results.csv");
  tally.finished = 75;
  tally.failed = 2;
  tally.held_elsewhere = 1;
  tally.time_limit_reached = 9000.0;
  EXPECT_EQ(sweep_end_line(tally, "out/results.csv"),
            "sweep: 75 of 80 runs finished, 2 failed (see their log.txt); 1 run still written "
            "by an earlier process, left for later (run the same command again); time limit "
            "2:30:00: 3 runs left for later (run the same command to resume); results in "
            "out/results.csv");
  tally = SweepTally{};
  tally.total = 10;
  tally.finished = 4;
  tally.interrupted = true;
  tally.write_error = "cannot write out/points.csv: No space left on device";
  tally.not_started = 5;
  EXPECT_EQ(sweep_end_line(tally, "out/results.csv"),
            "sweep: 4 of 10 runs finished (interrupted: run the same command to resume); "
            "stopped starting runs after a write error (cannot write out/points.csv: No space "
            "left on device): free space and run the same command to go on; the finished runs "
            "are kept, 5 not started; results in out/results.csv");
}

}  // namespace
}  // namespace cdpowder
