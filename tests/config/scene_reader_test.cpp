// Tests for src/cdpowder/config/scene_reader.cpp: defaults, overrides, every class of bad
// input (message names file:line:column, key, value and allowed range) and the effective
// TOML re-reading to the same Scene.
#include "cdpowder/config/scene_reader.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <sys/stat.h>  // mkfifo
#include <vector>

namespace cdpowder {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr const char* kParticles = "[particles]\nfile = \"p.csv\"\n";

/// A fresh directory holding a valid particles file p.csv, removed at the end of the test.
class SceneReader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cdpowder_scene_reader_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "p.csv") << "x,y,z,r\n1,1,1,1\n";
  }

  void TearDown() override { fs::remove_all(dir_); }

  Scene read(const std::string& text, const std::vector<SceneOverride>& overrides = {}) {
    return read_scene_text(text, "scene.toml", overrides, dir_);
  }

  /// The formatted issues of a text that must fail to read.
  std::vector<std::string> issues(const std::string& text,
                                  const std::vector<SceneOverride>& overrides = {}) {
    std::vector<std::string> result;
    try {
      read(text, overrides);
      ADD_FAILURE() << "no ConfigError for:\n" << text;
    } catch (const ConfigError& error) {
      for (const ConfigIssue& issue : error.issues()) {
        result.push_back(format(issue));
      }
    }
    return result;
  }

  fs::path dir_;
};

TEST_F(SceneReader, UsesTheStructDefaultsForAbsentKeys) {
  const Scene s = read(kParticles);
  const Scene d;  // the in-class defaults of scene.hpp and settings.hpp
  EXPECT_EQ(s.system.lx, d.system.lx);
  EXPECT_EQ(s.system.ly, d.system.ly);
  EXPECT_EQ(s.system.gravity, d.system.gravity);
  EXPECT_EQ(s.system.density, d.system.density);
  EXPECT_EQ(s.system.bottom_wall, d.system.bottom_wall);
  const ContactLaws& laws = s.step.laws;
  EXPECT_EQ(laws.spheres.mu, d.step.laws.spheres.mu);
  EXPECT_EQ(laws.spheres.mu_roll, d.step.laws.spheres.mu_roll);
  EXPECT_EQ(laws.spheres.cohesion_force, d.step.laws.spheres.cohesion_force);
  EXPECT_EQ(laws.spheres.cohesion_range, d.step.laws.spheres.cohesion_range);
  EXPECT_EQ(laws.cohesion_rule, d.step.laws.cohesion_rule);
  EXPECT_EQ(laws.walls.mu, laws.spheres.mu);
  EXPECT_EQ(laws.walls.cohesion_range, laws.spheres.cohesion_range);
  EXPECT_EQ(laws.wall_r_eff_factor, d.step.laws.wall_r_eff_factor);
  const SolverSettings& solver = s.step.solver;
  EXPECT_EQ(solver.dt, d.step.solver.dt);
  EXPECT_EQ(solver.tolerance, d.step.solver.tolerance);
  EXPECT_EQ(solver.min_passes, d.step.solver.min_passes);
  EXPECT_EQ(solver.max_passes, d.step.solver.max_passes);
  EXPECT_EQ(solver.stopping_rule, d.step.solver.stopping_rule);
  EXPECT_EQ(solver.visit_order, d.step.solver.visit_order);
  EXPECT_EQ(solver.acceleration_depth, d.step.solver.acceleration_depth);
  EXPECT_EQ(solver.skin, d.step.solver.skin);
  EXPECT_EQ(solver.seed, d.step.solver.seed);
  EXPECT_EQ(s.piston.enabled, d.piston.enabled);
  EXPECT_EQ(s.piston.mass, d.piston.mass);
  EXPECT_FALSE(s.piston.pressure.has_value());
  EXPECT_FALSE(s.piston.force.has_value());
  EXPECT_FALSE(s.piston.height.has_value());
  EXPECT_EQ(s.run.duration, d.run.duration);
  EXPECT_EQ(s.run.max_duration, d.run.max_duration);
  EXPECT_EQ(s.run.timeseries_every, d.run.timeseries_every);
  EXPECT_EQ(s.run.blocked.window, d.run.blocked.window);
  EXPECT_EQ(s.run.blocked.sphere_speed, d.run.blocked.sphere_speed);
  EXPECT_EQ(s.particles_file, dir_ / "p.csv");
  EXPECT_EQ(s.source, fs::path("scene.toml"));
}

TEST_F(SceneReader, ReadsValuesAndAcceptsIntegersForNumbers) {
  const Scene s = read(std::string(kParticles) +
                       "[system]\nlx = 30\ngravity = [0, 0, -1.5]\n"
                       "[contact]\nmu_roll = 0.25\ncohesion_rule = \"history\"\n"
                       "[solver]\nstopping_rule = \"relative_change\"\n"
                       "kinematic_norm = \"rms\"\n"
                       "visit_order = \"random_each_pass\"\nacceleration_depth = 0\n"
                       "acceleration_interval = 2\n"
                       "seed = 7\nwarm_start = false\n"
                       "[run.blocked]\nwindow = 5\n");
  EXPECT_EQ(s.system.lx, 30.0);
  EXPECT_EQ(s.system.gravity, Vec3(0.0, 0.0, -1.5));
  EXPECT_EQ(s.step.laws.spheres.mu_roll, 0.25);
  EXPECT_EQ(s.step.laws.cohesion_rule, CohesionRule::History);
  EXPECT_EQ(s.step.solver.stopping_rule, StoppingRule::RelativeChange);
  EXPECT_EQ(s.step.solver.kinematic_norm, KinematicNorm::Rms);
  EXPECT_EQ(s.step.solver.visit_order, VisitOrder::RandomEachPass);
  EXPECT_EQ(s.step.solver.acceleration_depth, 0);
  EXPECT_EQ(s.step.solver.acceleration_interval, 2);
  EXPECT_EQ(s.step.solver.seed, 7U);
  EXPECT_FALSE(s.step.solver.warm_start);
  EXPECT_EQ(s.run.blocked.window, 5.0);
}

TEST_F(SceneReader, WallLawDefaultsToContactLawAfterOverrides) {
  const Scene s = read(std::string(kParticles) + "[contact]\nmu = 0.4\nmu_twist = 0.2\n" +
                           "[contact.wall]\nmu_twist = 0.0\nr_eff_factor = 0.5\n",
                       {"contact.mu=0.6"});
  EXPECT_EQ(s.step.laws.spheres.mu, 0.6);
  EXPECT_EQ(s.step.laws.walls.mu, 0.6);
  EXPECT_EQ(s.step.laws.walls.mu_twist, 0.0);
  EXPECT_EQ(s.step.laws.wall_r_eff_factor, 0.5);
}

TEST_F(SceneReader, NamesFileLineKeyValueAndRangeOfOutOfRangeValue) {
  const auto found = issues(std::string(kParticles) + "[contact]\nmu_roll =  -0.2\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0], "scene.toml:4:12: contact.mu_roll: got -0.2, expected a number ≥ 0");
}

TEST_F(SceneReader, RejectsZeroWhereAPositiveNumberIsNeeded) {
  const auto found = issues(std::string(kParticles) + "[solver]\ndt = 0\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0], "scene.toml:4:6: solver.dt: got 0, expected a number > 0");
}

TEST_F(SceneReader, RejectsNonFiniteNumbers) {
  const auto found = issues(std::string(kParticles) + "[system]\nlx = inf\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("system.lx"), HasSubstr("got inf"), HasSubstr("finite")));
}

TEST_F(SceneReader, ReportsWrongTypes) {
  const auto found = issues(std::string(kParticles) +
                            "[contact]\nmu = \"high\"\n"
                            "[solver]\nmax_passes = 2.5\nwarm_start = 1\n"
                            "[system]\ngravity = [0, -1]\n");
  ASSERT_EQ(found.size(), 4U);
  EXPECT_EQ(found[0], "scene.toml:4:6: contact.mu: got \"high\", expected a number ≥ 0");
  EXPECT_THAT(found[1],
              AllOf(HasSubstr("scene.toml:6:"), HasSubstr("solver.max_passes"),
                    HasSubstr("got 2.5 (a floating-point number), expected an integer ≥ 1")));
  EXPECT_THAT(found[2], AllOf(HasSubstr("solver.warm_start"), HasSubstr("true or false")));
  EXPECT_THAT(found[3], AllOf(HasSubstr("system.gravity"), HasSubstr("array of 3 numbers")));
}

TEST_F(SceneReader, RejectsIntegersOutsideTheirRange) {
  const auto found = issues(std::string(kParticles) +
                            "[solver]\nseed = -1\nmax_passes = 3000000000\n"
                            "acceleration_interval = 0\n"
                            "[run]\ntimeseries_every = 0\n");
  ASSERT_EQ(found.size(), 4U);
  EXPECT_EQ(found[0], "scene.toml:4:8: solver.seed: got -1, expected an integer ≥ 0");
  EXPECT_THAT(found[1], HasSubstr("got 3000000000, expected an integer ≤ 2147483647"));
  EXPECT_THAT(found[2], HasSubstr("solver.acceleration_interval: got 0, expected an integer ≥ 1"));
  EXPECT_THAT(found[3], HasSubstr("run.timeseries_every: got 0, expected an integer ≥ 1"));
}

// 1e9 and 10.0 are TOML floats: the message says so and how to write the integer
TEST_F(SceneReader, AnIntegerWrittenAsAFloatIsNamedAsSuch) {
  const auto found = issues(std::string(kParticles) +
                            "[solver]\nmax_passes = 1e3\n"
                            "[run]\ntimeseries_every = 2.5\n");
  ASSERT_EQ(found.size(), 2U);
  EXPECT_THAT(found[0], HasSubstr("solver.max_passes: got 1000 (written as a floating-point "
                                  "number; write 1000), expected an integer ≥ 1"));
  EXPECT_THAT(found[1], HasSubstr("got 2.5 (a floating-point number)"));
}

TEST_F(SceneReader, LimitsTheDepositToTenMillionSpheres) {
  const std::string deposit = "[deposition]\nspheres = {}\n[system]\nlx = 20.0\nly = 20.0\n";
  EXPECT_NO_THROW(read(fmt::format(fmt::runtime(deposit), 10'000'000)));
  const auto found = issues(fmt::format(fmt::runtime(deposit), 10'000'001));
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("deposition.spheres: got 10000001, expected an integer ≤ "
                                  "10000000"));
}

// A capture sphere wider than half the periodic cell reaches a sphere's own images; a first
// step longer than the run makes a run of no step
TEST_F(SceneReader, RejectsACaptureRadiusBeyondHalfTheCellAndAStepLongerThanTheRun) {
  const std::string deposit =
      "[deposition]\nspheres = 10\ncapture_radius = {}\n[system]\nlx = 20.0\nly = 12.0\n";
  EXPECT_NO_THROW(read(fmt::format(fmt::runtime(deposit), 6.0)));
  auto found = issues(fmt::format(fmt::runtime(deposit), 6.000001));
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("deposition.capture_radius: got 6.000001, expected at most "
                                  "half the cell, min(system.lx, system.ly) / 2 = 6"));
  EXPECT_NO_THROW(read(std::string(kParticles) + "[solver]\ndt = 0.5\n[run]\nduration = 0.5\n"));
  found = issues(std::string(kParticles) + "[solver]\ndt = 0.6\n[run]\nduration = 0.5\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("solver.dt: got 0.6, expected at most run.duration = 0.5"));
  // nor so short that the run could never end (1e-300 once "ran" zero steps, exit 0)
  found = issues(std::string(kParticles) + "[solver]\ndt = 1e-300\n[run]\nduration = 1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("solver.dt: got 1e-300, expected at least run.duration / "
                                  "1e12 = 1e-12 (a run of more than 10^12 steps could not end)"));
  // with the adaptive step the bound is on the shortest step it may take
  found = issues(std::string(kParticles) +
                 "[solver]\nadaptive_dt = true\ndt_min = 1e-300\n[run]\nduration = 1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("solver.dt_min: got 1e-300, expected at least run.duration"));
}

TEST_F(SceneReader, EchoesAtMostFortyCharactersOfAValue) {
  const auto found = issues(std::string(kParticles) + "[solver]\nvisit_order = \"" +
                            std::string(5000, 'q') + "\"\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("\"" + std::string(40, 'q') + "… (5000 characters)\""));
  EXPECT_LT(found[0].size(), 300U);
}

TEST_F(SceneReader, ReportsAKnownTableThatIsNotATable) {
  const auto found = issues(std::string("solver = 3\n") + kParticles);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0], "scene.toml:1:1: solver: got 3, expected a table");
}

TEST_F(SceneReader, RejectsUnknownKeysWithSuggestion) {
  const auto found = issues(std::string(kParticles) +
                            "[solver]\ntolerence = 1e-6\n[solvr]\ndt = 0.1\n[piston]\nmu = 1\n"
                            "[system]\nspheres = 10\n");
  ASSERT_EQ(found.size(), 4U);
  EXPECT_EQ(found[0],
            "scene.toml:4:1: solver.tolerence: unknown key; did you mean "
            "'solver.tolerance'?");
  EXPECT_THAT(found[1], AllOf(HasSubstr("scene.toml:5:"), HasSubstr("did you mean 'solver'?")));
  EXPECT_THAT(found[2], HasSubstr("piston.mu: unknown key; did you mean 'contact.mu'?"));
  EXPECT_THAT(found[3], HasSubstr("system.spheres: unknown key"));
  EXPECT_THAT(found[3], ::testing::Not(HasSubstr("did you mean")));
}

TEST_F(SceneReader, RejectsBadEnumStringListingTheAllowedOnes) {
  const auto found = issues(std::string(kParticles) +
                            "[contact]\ncohesion_rule = \"grpah\"\n"
                            "[solver]\nvisit_order = \"sorted\"\n"
                            "kinematic_norm = \"mean\"\n");
  ASSERT_EQ(found.size(), 3U);
  EXPECT_EQ(found[0],
            "scene.toml:4:17: contact.cohesion_rule: got \"grpah\", expected one of "
            "\"graph\", \"history\"; did you mean 'graph'?");
  EXPECT_THAT(found[1], HasSubstr("expected one of \"random_each_step\", \"random_each_pass\", "
                                  "\"fixed\""));
  EXPECT_THAT(found[2], HasSubstr("solver.kinematic_norm: got \"mean\", expected one of \"max\", "
                                  "\"rms\""));
}

TEST_F(SceneReader, RejectsPressureAndForceTogether) {
  const auto found = issues(std::string(kParticles) +
                            "[piston]\nenabled = true\npressure = 0.0025\nforce = 1.5\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("scene.toml:6:"), HasSubstr("piston.force"),
                              HasSubstr("piston.pressure")));
}

TEST_F(SceneReader, RejectsEnabledPistonWithoutPush) {
  const auto found = issues(std::string(kParticles) + "[piston]\nenabled = true\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("piston.enabled"), HasSubstr("piston.pressure"),
                              HasSubstr("piston.force")));
}

// a scene without a piston (a gravity settling) may run until the spheres alone are blocked;
// a compaction still needs the piston
TEST_F(SceneReader, AcceptsUntilBlockedWithoutAPistonButNotACompaction) {
  const std::string text = std::string(kParticles) + "[run]\nuntil_blocked = true\n";
  EXPECT_TRUE(read(text).run.until_blocked);
  SceneReadOptions compaction;
  compaction.compaction = true;
  try {
    (void)read_scene_text(text, "scene.toml", {}, dir_, compaction);
    ADD_FAILURE() << "a compaction without a piston was read";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("compaction needs the piston"));
  }
}

TEST_F(SceneReader, RejectsMinPassesAboveMaxPasses) {
  const auto found =
      issues(std::string(kParticles) + "[solver]\nmin_passes = 50\nmax_passes = 10\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0],
              AllOf(HasSubstr("solver.min_passes: got 50"), HasSubstr("solver.max_passes = 10")));
}

// Scene files written before the NLGS pass was called a pass still read, and their messages
// name the keys as written.
TEST_F(SceneReader, ReadsTheFormerNamesOfThePassKeys) {
  const Scene s = read(std::string(kParticles) +
                       "[solver]\nmin_sweeps = 4\nmax_sweeps = 40\n"
                       "visit_order = \"random_each_sweep\"\n"
                       "[run.blocked]\nfinal_max_sweeps = 300\n");
  EXPECT_EQ(s.step.solver.min_passes, 4);
  EXPECT_EQ(s.step.solver.max_passes, 40);
  EXPECT_EQ(s.step.solver.visit_order, VisitOrder::RandomEachPass);
  EXPECT_EQ(s.run.blocked.final_max_passes, 300);
  EXPECT_THAT(s.effective_toml, HasSubstr("max_passes = 40\n"));
  EXPECT_THAT(s.effective_toml, Not(HasSubstr("sweep")));

  const auto bad = issues(std::string(kParticles) + "[solver]\nmax_sweeps = 0\n");
  ASSERT_EQ(bad.size(), 1U);
  EXPECT_THAT(bad[0], HasSubstr("scene.toml:4:14: solver.max_sweeps: got 0"));

  const auto both = issues(std::string(kParticles) + "[solver]\nmax_sweeps = 9\nmax_passes = 9\n");
  ASSERT_EQ(both.size(), 1U);
  EXPECT_THAT(both[0], HasSubstr("solver.max_sweeps: is the former name of 'solver.max_passes'"));
}

// solver.threads splits the coloured kernel's passes; the scalar kernel has one thread.
TEST_F(SceneReader, ReadsThreadsWithTheColouredKernelAndWritesThemBack) {
  const Scene s = read(std::string(kParticles) + "[solver]\nthreads = 2\n");  // coloured: default
  EXPECT_EQ(s.step.solver.threads, 2);
  EXPECT_THAT(s.effective_toml, HasSubstr("threads = 2\n"));
  EXPECT_EQ(read(kParticles).step.solver.threads, 1);
  // "auto" is 0, every usable core, written back as 0; another word is refused by name
  const Scene automatic = read(std::string(kParticles) + "[solver]\nthreads = \"auto\"\n");
  EXPECT_EQ(automatic.step.solver.threads, 0);
  EXPECT_THAT(automatic.effective_toml, HasSubstr("threads = 0\n"));
  EXPECT_EQ(read(kParticles, {"solver.threads=\"auto\""}).step.solver.threads, 0);
  const auto word = issues(std::string(kParticles) + "[solver]\nthreads = \"all\"\n");
  ASSERT_EQ(word.size(), 1U);
  EXPECT_THAT(word[0], AllOf(HasSubstr("solver.threads"), HasSubstr("\"auto\"")));
}

TEST_F(SceneReader, RejectsThreadsWithTheScalarKernel) {
  const auto found =
      issues(std::string(kParticles) + "[solver]\nkernel = \"scalar\"\nthreads = 2\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0],
              AllOf(HasSubstr("scene.toml:5:11: solver.threads: got 2"),
                    HasSubstr("solver.kernel = \"scalar\""),
                    HasSubstr("expected 1, or solver.kernel = \"coloured\" for 1 to 1024")));
  const auto from_set = issues(kParticles, {"solver.kernel=\"scalar\"", "solver.threads=3"});
  ASSERT_EQ(from_set.size(), 1U);
  EXPECT_THAT(from_set[0], HasSubstr("solver.threads: got 3"));
  // 0 is every usable core; a negative count is refused
  EXPECT_EQ(read(std::string(kParticles) + "[solver]\nthreads = 0\n").step.solver.threads, 0);
  const auto negative = issues(std::string(kParticles) + "[solver]\nthreads = -1\n");
  ASSERT_EQ(negative.size(), 1U);
  EXPECT_THAT(negative[0], HasSubstr("solver.threads: got -1"));
}

TEST_F(SceneReader, RejectsAFinalSolveWithoutPasses) {
  const auto found = issues(std::string(kParticles) + "[run.blocked]\nfinal_max_passes = 0\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("run.blocked.final_max_passes: got 0"));
}

TEST_F(SceneReader, RejectsABlockedWindowOfMoreThanAMillionSteps) {
  const auto found = issues(std::string(kParticles) +
                            "[piston]\nenabled = true\npressure = 0.0025\n"
                            "[run]\nuntil_blocked = true\n[run.blocked]\nwindow = 2e4\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0],
              AllOf(HasSubstr("run.blocked.window: got 20000"), HasSubstr("solver.dt = 0.01")));
}

TEST_F(SceneReader, ReportsEveryIssueOfAFileAtOnce) {
  const auto found = issues("[contact]\nmu = -1\nmu_roll = -1\n[solver]\ndt = -1\nbad = 1\n");
  // Three ranges, one unknown key, and the missing [particles] file.
  EXPECT_EQ(found.size(), 5U);
}

TEST_F(SceneReader, RequiresTheParticlesFile) {
  // no spheres at all (an empty scene file once said only "particles.file: missing")
  const auto none = issues("[system]\nlx = 30\n");
  ASSERT_EQ(none.size(), 1U);
  EXPECT_EQ(none[0],
            "scene.toml: particles: missing: the spheres come from a [deposition] section (a "
            "ballistic deposit) or a [particles] file = \"….csv\" (docs/config.md)");
  const auto found = issues("[system]\nlx = 30\n[particles]\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0], "scene.toml: particles.file: missing; this key is required");
}

TEST_F(SceneReader, SaysWhatAParticlesFileThatIsNotAFileIs) {
  fs::create_directories(dir_ / "folder.csv");
  const auto found = issues("[particles]\nfile = \"folder.csv\"\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("scene.toml:2:8: particles.file: '"),
                              HasSubstr("folder.csv' is a folder; expected a particles CSV")));
}

TEST_F(SceneReader, ReportsAParticlesFileThatDoesNotExist) {
  const auto found = issues("[particles]\nfile = \"missing.csv\"\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("scene.toml:2:8: particles.file: no such file"),
                              HasSubstr("missing.csv")));
}

TEST_F(SceneReader, ReportsTomlSyntaxErrorWithLineAndColumn) {
  const auto found = issues("[system]\nlx = = 3\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("scene.toml:2:"));
  EXPECT_THAT(found[0], HasSubstr("TOML syntax error"));
}

TEST_F(SceneReader, OverrideReplacesFileValueAndCreatesTables) {
  const Scene s = read(
      std::string(kParticles) + "[contact]\nmu_roll = 0.1\n",
      {"contact.mu_roll=0.5", "solver.seed = 7", "piston.enabled=true", "piston.pressure=0.0025",
       "system.gravity=[0,0,-1]", "contact.wall.mu_roll=0", "solver.visit_order=\"fixed\""});
  EXPECT_EQ(s.step.laws.spheres.mu_roll, 0.5);
  EXPECT_EQ(s.step.laws.walls.mu_roll, 0.0);
  EXPECT_EQ(s.step.solver.seed, 7U);
  EXPECT_TRUE(s.piston.enabled);
  EXPECT_EQ(s.piston.pressure, 0.0025);
  EXPECT_EQ(s.system.gravity, Vec3(0.0, 0.0, -1.0));
  EXPECT_EQ(s.step.solver.visit_order, VisitOrder::Fixed);
  EXPECT_THAT(s.effective_toml, HasSubstr("mu_roll = 0.5"));
}

TEST_F(SceneReader, LaterOverrideWins) {
  const Scene s = read(kParticles, {"solver.dt=0.1", "solver.dt=0.005"});
  EXPECT_EQ(s.step.solver.dt, 0.005);
}

TEST_F(SceneReader, ReportsMalformedOverrides) {
  const auto found =
      issues(kParticles, {"contact.mu_roll", "contact.mu_roll=0..5", "=3", "contact..mu=1",
                          "contact.mu=", "solver.visit_order=fixed"});
  ASSERT_EQ(found.size(), 6U);
  EXPECT_EQ(found[0],
            "--set: contact.mu_roll: malformed override, expected section.key=value "
            "(e.g. contact.mu_roll=0.5)");
  EXPECT_THAT(found[1], AllOf(HasSubstr("--set: contact.mu_roll: malformed override"),
                              HasSubstr("'contact.mu_roll=0..5'")));
  EXPECT_THAT(found[2], HasSubstr("--set: =3: malformed override"));
  EXPECT_THAT(found[3], HasSubstr("--set: contact..mu=1: malformed override"));
  EXPECT_THAT(found[4], HasSubstr("--set: contact.mu: malformed override"));
  EXPECT_THAT(found[5], HasSubstr("strings need quotes: \"fixed\""));
}

// A key with a character TOML's bare keys do not allow once read "malformed override,
// expected section.key=value" though it had that form
TEST_F(SceneReader, SaysWhichCharactersAnOverrideKeyMayHold) {
  const auto found = issues(kParticles, {"contact.µ=1"});
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0],
            "--set: contact.µ: malformed override: a key holds only the letters a-z "
            "and A-Z, digits, '_', '-' and '.' (e.g. contact.mu_roll=0.5)");
}

TEST_F(SceneReader, ReportsOverrideOfUnknownKeyAsSet) {
  const auto found = issues(kParticles, {"contact.mu_rol=0.5", "compaction.pressure=1"});
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0], "--set: compaction: unknown key");
  EXPECT_EQ(found[1], "--set: contact.mu_rol: unknown key; did you mean 'contact.mu_roll'?");
}

TEST_F(SceneReader, ReportsBadOverrideValueAsSet) {
  const auto found = issues(kParticles, {"contact.mu_roll=-0.5", "particles.file.x=1"});
  ASSERT_EQ(found.size(), 2U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("--set: particles.file.x"), HasSubstr("not a table")));
  EXPECT_EQ(found[1], "--set: contact.mu_roll: got -0.5, expected a number ≥ 0");
}

TEST_F(SceneReader, ReportsAnOverrideWhereItWasWritten) {
  // a sweep file's `set` and grid values carry their place in the sweep file; a created
  // table is reported where its first value came from
  const auto found = issues(kParticles, {{"contact.mu=-1", "sweep.toml:3:8"},
                                         {"compaction.pressure=1", "sweep.toml:7:20"},
                                         {"contact.mu_roll", "sweep.toml:9:2"}});
  ASSERT_EQ(found.size(), 3U);
  EXPECT_EQ(found[0],
            "sweep.toml:9:2: contact.mu_roll: malformed override, expected section.key=value "
            "(e.g. contact.mu_roll=0.5)");
  EXPECT_EQ(found[1], "sweep.toml:3:8: contact.mu: got -1, expected a number ≥ 0");
  EXPECT_EQ(found[2], "sweep.toml:7:20: compaction: unknown key");
}

TEST_F(SceneReader, ReportsAParticlesFileOfTheCommandAsParticles) {
  SceneReadOptions options;
  options.particles_file = dir_ / "missing.csv";
  try {
    (void)read_scene_text(kParticles, "scene.toml", {}, dir_, options);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1U);
    EXPECT_EQ(format(error.issues()[0]),
              fmt::format("--particles: particles.file: no such file: '{}'",
                          (dir_ / "missing.csv").string()));
  }
  options.particles_file = dir_ / "p.csv";  // and a good one is read
  EXPECT_EQ(read_scene_text(kParticles, "scene.toml", {}, dir_, options).particles_file,
            dir_ / "p.csv");
}

TEST_F(SceneReader, ReadsAFileAndResolvesParticlesAgainstItsFolder) {
  fs::create_directories(dir_ / "scenes");
  std::ofstream(dir_ / "scenes" / "s.toml") << "[particles]\nfile = \"../p.csv\"\n";
  const Scene s = read_scene(dir_ / "scenes" / "s.toml", {});
  EXPECT_EQ(s.particles_file, dir_ / "p.csv");
  EXPECT_EQ(s.source, dir_ / "scenes" / "s.toml");
}

TEST_F(SceneReader, ReportsAMissingSceneFile) {
  try {
    read_scene(dir_ / "nope.toml", {});
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1U);
    EXPECT_EQ(error.issues()[0].file, (dir_ / "nope.toml").string());
    EXPECT_THAT(error.what(), HasSubstr("nope.toml: no such file; expected a scene file"));
  }
}

// An empty name, and a FIFO (whose open blocks until a writer comes: the command hung)
TEST_F(SceneReader, SaysWhyASceneFileCannotBeRead) {
  const auto message = [](const fs::path& file) {
    try {
      (void)read_scene(file, {});
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string("no ConfigError");
  };
  EXPECT_EQ(message(""),
            "the file name is empty; expected a scene file (TOML), e.g. examples/quick/scene.toml");
  const fs::path fifo = dir_ / "fifo.toml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(message(fifo), fifo.string() +
                               ": is not a regular file (a FIFO, socket or device); expected a "
                               "scene file (TOML), e.g. examples/quick/scene.toml");
}

// A folder opens as an empty stream on Linux: before, it read as a scene without keys
// ("particles.file: missing").
TEST_F(SceneReader, SaysAFolderIsNotASceneFile) {
  try {
    read_scene(dir_, {});
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1U);
    EXPECT_THAT(error.what(), HasSubstr("is a folder; expected a scene file"));
  }
}

TEST_F(SceneReader, EffectiveTomlRereadsToTheSameScene) {
  const Scene a = read(std::string(kParticles) +
                           "[system]\nlx = 12.5\ngravity = [0.1, 0, -9.81]\nbottom_wall = false\n"
                           "[contact]\nmu = 0.3\nmu_roll = 0.1\ncohesion_rule = \"history\"\n"
                           "[contact.wall]\ncohesion_force = 2\n"
                           "[solver]\ntolerance = 1e-7\nvisit_order = \"fixed\"\nseed = 42\n"
                           "[piston]\nenabled = true\nforce = 1.5625\nheight = 40.25\n"
                           "[run]\nuntil_blocked = true\ntimeseries_every = 10\n",
                       {"run.blocked.height_change=3e-6", "run.blocked.final_tolerance=1e-8",
                        "run.blocked.final_max_passes=1234"});
  EXPECT_THAT(a.effective_toml, AllOf(HasSubstr("mu = 0.3\n"), HasSubstr("tolerance = 1e-07")));
  const Scene b = read_scene_text(a.effective_toml, "effective.toml", {}, "/elsewhere");
  EXPECT_EQ(b.effective_toml, a.effective_toml);
  EXPECT_EQ(b.system.lx, 12.5);
  EXPECT_EQ(b.system.gravity, a.system.gravity);
  EXPECT_FALSE(b.system.bottom_wall);
  EXPECT_EQ(b.step.laws.spheres.mu, a.step.laws.spheres.mu);
  EXPECT_EQ(b.step.laws.spheres.mu_roll, 0.1);
  EXPECT_EQ(b.step.laws.walls.cohesion_force, 2.0);
  EXPECT_EQ(b.step.laws.walls.mu_roll, 0.1);
  EXPECT_EQ(b.step.laws.cohesion_rule, CohesionRule::History);
  EXPECT_EQ(b.step.solver.tolerance, 1e-7);
  EXPECT_EQ(b.step.solver.visit_order, VisitOrder::Fixed);
  EXPECT_EQ(b.step.solver.seed, 42U);
  EXPECT_TRUE(b.piston.enabled);
  EXPECT_EQ(b.piston.force, 1.5625);
  EXPECT_FALSE(b.piston.pressure.has_value());
  EXPECT_EQ(b.piston.height, 40.25);
  EXPECT_TRUE(b.run.until_blocked);
  EXPECT_EQ(b.run.timeseries_every, 10);
  EXPECT_EQ(b.run.blocked.height_change, 3e-6);
  EXPECT_EQ(b.run.blocked.final_tolerance, 1e-8);
  EXPECT_EQ(b.run.blocked.final_max_passes, 1234);
  EXPECT_EQ(b.particles_file, a.particles_file);
}

}  // namespace
}  // namespace cdpowder

namespace cdpowder {
namespace {

using ::testing::HasSubstr;

/// The formatted issues of a scene text read with `options` (empty if it reads).
std::vector<std::string> issues_with(const std::string& text, const SceneReadOptions& options) {
  std::vector<std::string> result;
  try {
    read_scene_text(text, "scene.toml", {}, std::filesystem::temp_directory_path(), options);
  } catch (const ConfigError& error) {
    for (const ConfigIssue& issue : error.issues()) result.push_back(format(issue));
  }
  return result;
}

// The adaptive time step's keys (settings.hpp TimeStepControl): read, written back, and
// their ranges and relations checked.
TEST_F(SceneReader, ReadsTheAdaptiveTimeStepKeys) {
  const Scene s = read(std::string(kParticles) +
                       "[solver]\nadaptive_dt = true\ndt = 0.02\ndt_min = 0.001\ndt_max = 0.1\n"
                       "opening_per_step = 0.04\nmax_opening_per_step = 0.08\n"
                       "displacement_per_step = 0.3\ndt_growth = 1.5\n");
  const TimeStepControl& c = s.step.solver.time_step;
  EXPECT_TRUE(c.adaptive);
  EXPECT_EQ(c.dt_min, 0.001);
  EXPECT_EQ(c.dt_max, 0.1);
  EXPECT_EQ(c.opening_per_step, 0.04);
  EXPECT_EQ(c.max_opening_per_step, 0.08);
  EXPECT_EQ(c.displacement_per_step, 0.3);
  EXPECT_EQ(c.growth, 1.5);
  const Scene again = read(s.effective_toml);
  EXPECT_EQ(again.effective_toml, s.effective_toml);
}

TEST_F(SceneReader, AnAdaptiveDtMustStartWithinItsBounds) {
  const auto found =
      issues(std::string(kParticles) + "[solver]\nadaptive_dt = true\ndt = 0.2\ndt_max = 0.1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("solver.dt_max"), HasSubstr("solver.dt = 0.2"),
                              HasSubstr("≤ solver.dt_max = 0.1")));
  // without adaptive_dt the bounds do not apply
  EXPECT_NO_THROW(read(std::string(kParticles) + "[solver]\ndt = 0.2\ndt_max = 0.1\n"));
}

TEST_F(SceneReader, TheOpeningTargetMustNotExceedItsBound) {
  const auto found = issues(std::string(kParticles) +
                            "[solver]\nopening_per_step = 0.2\nmax_opening_per_step = 0.1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("solver.opening_per_step: got 0.2"),
                              HasSubstr("solver.max_opening_per_step = 0.1")));
  const auto fraction = issues(std::string(kParticles) + "[solver]\ndisplacement_per_step = 1.5\n");
  ASSERT_EQ(fraction.size(), 1U);
  EXPECT_THAT(fraction[0], AllOf(HasSubstr("solver.displacement_per_step"), HasSubstr("got 1.5"),
                                 HasSubstr("> 0 and ≤ 1")));
  const auto growth = issues(std::string(kParticles) + "[solver]\ndt_growth = 0.9\n");
  ASSERT_EQ(growth.size(), 1U);
  EXPECT_THAT(growth[0], AllOf(HasSubstr("solver.dt_growth"), HasSubstr("≥ 1")));
}

TEST(DepositionSection, ReadsEveryKeyAndDerivesTheCell) {
  const Scene s = read_scene_text(
      "[system]\nlx = 12.0\nly = 8.0\n[deposition]\nspheres = 50\nradius_min = 0.5\n"
      "radius_max = 1.5\ncapture_radius = 0.5\ncapture_rule = \"surface_gap\"\nseed = 9\n",
      "scene.toml", {}, std::filesystem::temp_directory_path());
  ASSERT_TRUE(s.deposition.has_value());
  EXPECT_EQ(s.deposition->spheres, 50);
  EXPECT_EQ(s.deposition->lx, 12.0);
  EXPECT_EQ(s.deposition->ly, 8.0);
  EXPECT_EQ(s.deposition->capture_rule, CaptureRule::SurfaceGap);
  EXPECT_EQ(s.deposition->capture_gap(), 0.5);
  EXPECT_EQ(s.deposition->seed, 9U);
}

TEST(DepositionSection, AMisspeltKeyIsAnUnknownKey) {
  const auto found = issues_with("[deposition]\ncapture_raduis = 2.0\n", {});
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("deposition.capture_raduis: unknown key"));
  EXPECT_THAT(found[0], HasSubstr("did you mean 'deposition.capture_radius'"));
}

TEST(DepositionSection, MustBeATable) {
  const auto found = issues_with("deposition = 5\n[particles]\nfile = \"x.csv\"\n", {});
  EXPECT_THAT(found, ::testing::Contains(HasSubstr("deposition: got 5, expected a table")));
}

TEST(DepositionSection, RadiusAndARangeTogetherAreRefused) {
  const auto found =
      issues_with("[deposition]\nradius = 1.0\nradius_min = 0.5\nradius_max = 1.5\n", {});
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("deposition.radius: set together with radius_min"));
}

// An override of one radius key replaces the file's other form: a monodisperse scene made
// polydisperse with --set, and back (the file alone may not give both forms)
TEST(DepositionSection, RadiusOverridesReplaceTheFilesOtherForm) {
  const std::string mono = "[deposition]\nspheres = 10\nradius = 1.0\n";
  const Scene spread =
      read_scene_text(mono, "scene.toml", {SceneOverride("deposition.radius_max=1.5")}, ".");
  EXPECT_EQ(spread.deposition->radius_min, 1.0);
  EXPECT_EQ(spread.deposition->radius_max, 1.5);
  // the keys read as every override's are, spaces around them trimmed: both ends given
  // replace the file's radius instead of conflicting with it
  const Scene spaced = read_scene_text(mono, "scene.toml",
                                       {SceneOverride(" deposition.radius_min = 0.8"),
                                        SceneOverride(" deposition.radius_max = 1.5")},
                                       ".");
  EXPECT_EQ(spaced.deposition->radius_min, 0.8);
  EXPECT_EQ(spaced.deposition->radius_max, 1.5);
  const std::string range = "[deposition]\nspheres = 10\nradius_min = 0.5\nradius_max = 1.5\n";
  const Scene narrowed =
      read_scene_text(range, "scene.toml", {SceneOverride("deposition.radius=0.8")}, ".");
  EXPECT_EQ(narrowed.deposition->radius_min, 0.8);
  EXPECT_EQ(narrowed.deposition->radius_max, 0.8);
  // both forms among the overrides still conflict
  try {
    (void)read_scene_text(
        mono, "scene.toml",
        {SceneOverride("deposition.radius=0.8"), SceneOverride("deposition.radius_min=0.5"),
         SceneOverride("deposition.radius_max=0.9")},
        ".");
    ADD_FAILURE() << "both radius forms were accepted";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("set together with radius_min"));
  }
}

TEST(DepositionSection, BesideParticlesIsReportedOnce) {
  const auto found = issues_with("[deposition]\n[particles]\nfile = \"x.csv\"\n", {});
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("given together with [deposition]"));
}

TEST(CompactionOptions, AnExplicitFixedDurationIsRefused) {
  SceneReadOptions compaction;
  compaction.compaction = true;
  const auto found = issues_with(
      "[deposition]\n[piston]\nenabled = true\npressure = 0.0025\n[run]\nuntil_blocked = false\n",
      compaction);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("run.until_blocked: is false, but compact always runs"));
  EXPECT_TRUE(issues_with("[deposition]\n[piston]\nenabled = true\npressure = 0.0025\n", compaction)
                  .empty());
}

}  // namespace
}  // namespace cdpowder
