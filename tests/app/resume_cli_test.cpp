// `cdpowder resume DIR` and `--checkpoint-every T`, run as processes: a run stopped by
// SIGKILL, SIGINT or a sweep's end and continued ends bit-identical to the run never stopped
// (docs/outputs.md, "Checkpoints and resume").
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/io/byte_stream.hpp"
#include "cdpowder/io/provenance.hpp"
#include "cdpowder/io/state_csv.hpp"
#include "cdpowder/io/timeseries.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "cdpowder/version.hpp"
#include "support/cli_process.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using cdpowder::testing::ProcessResult;
using cdpowder::testing::run_cdpowder;
using cdpowder::testing::run_process;
using cdpowder::testing::slurp;
using ::testing::HasSubstr;

const fs::path kQuick = CDPOWDER_SOURCE_DIR "/examples/quick/scene.toml";

// The quick scene at (μt, μn) = (0.2, 0.2): 21 249 steps, 2.3 s, blocked at t = 212 t0.
const std::string kScene = kQuick.string() +
                           " --set contact.mu_roll=0.2 --set contact.mu_twist=0.2"
                           " --set run.snapshot_every=700 --set run.timeseries_every=1";

using ResumeCli = cdpowder::testing::ScratchFolderTest;

/// summary.json without what differs from run to run of the same scene (wall and stage
/// times): every number of the physics, the counts and the scene.
nlohmann::json physics_of(const fs::path& summary) {
  nlohmann::json s = nlohmann::json::parse(slurp(summary));
  s["run"].erase("wall_seconds");
  s["run"].erase("stage_seconds");
  s["run"].erase("probe_seconds");
  return s;
}

/// Every output of an uninterrupted run in `a` is in `b` with the same bytes (the summary:
/// the same physics), and `b` holds nothing else but its log.
void expect_same_outputs(const fs::path& a, const fs::path& b) {
  for (const char* file :
       {"particles.csv", "contacts.csv", "timeseries.csv", "initial_particles.csv", "scene.toml",
        "particles.vtp", "contacts.vtp"}) {
    EXPECT_TRUE(slurp(a / file) == slurp(b / file)) << file << " differs";
  }
  EXPECT_EQ(physics_of(a / "summary.json"), physics_of(b / "summary.json"));
  std::vector<std::string> names_a;
  std::vector<std::string> names_b;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    names_a.push_back(fs::relative(e.path(), a).string());
  }
  for (const auto& e : fs::recursive_directory_iterator(b)) {
    const std::string name = fs::relative(e.path(), b).string();
    if (name != "killed.log") names_b.push_back(name);
  }
  std::sort(names_a.begin(), names_a.end());
  std::sort(names_b.begin(), names_b.end());
  EXPECT_EQ(names_a, names_b);
  for (const std::string& name : names_a) {
    if (name.starts_with("snapshots/") || name.ends_with(".pvd")) {
      EXPECT_TRUE(slurp(a / name) == slurp(b / name)) << name << " differs";
    }
  }
}

// SIGKILL after a checkpoint, while the run goes on past it: the time series has rows and
// the snapshots files beyond it. `resume` cuts them back and ends with every output as the
// run never stopped writes it. The killed run's log already names it.
TEST_F(ResumeCli, ARunKilledAfterACheckpointResumesBitIdentically) {
  const fs::path whole = scratch_ / "whole";
  ASSERT_EQ(run_cdpowder("compact " + kScene + " --quiet --out " + whole.string(), scratch_).status,
            0);
  const fs::path killed = scratch_ / "killed";
  const fs::path script = scratch_ / "kill.sh";
  // a checkpoint at t = 20 t0; killed once the snapshot at t = 28 t0 is listed
  std::ofstream(script) << CDPOWDER_EXE << " compact " << kScene << " --quiet --out "
                        << killed.string() << " --checkpoint-every 20 2> " << scratch_.string()
                        << "/killed.log &\npid=$!\n"
                        << "for i in $(seq 1 2000); do grep -q particles_000004 "
                        << (killed / "particles.pvd").string()
                        << " 2>/dev/null && break; sleep 0.005; done\n"
                        << "kill -KILL $pid\nwait $pid\n";
  run_process("sh", script.string(), scratch_);
  ASSERT_TRUE(fs::exists(killed / "checkpoint.cdps"));
  ASSERT_FALSE(fs::exists(killed / "summary.json"));  // killed, not finished
  const cdpowder::SavedRun saved = cdpowder::load_state(killed / "checkpoint.cdps");
  EXPECT_LT(saved.world.time, 28.0);
  // the log of the killed run says what ran
  const std::string log = slurp(scratch_ / "killed.log");
  EXPECT_THAT(log, HasSubstr(std::string("cdpowder ") + cdpowder::kVersion + " (commit " +
                             cdpowder::kGitCommit + "): compact " + kQuick.string()));
  EXPECT_THAT(log, HasSubstr("100 spheres, seed 1, deposition seed 1"));
  // past the checkpoint: time-series rows on disk, and a snapshot listed
  std::int64_t rows_past = 0;
  for (const auto& e : fs::directory_iterator(killed)) {
    if (e.path().filename().string().starts_with(".timeseries.csv.")) {
      rows_past = cdpowder::cut_timeseries(e.path(), 1'000'000).rows -
                  cdpowder::cut_timeseries(e.path(), saved.world.step).rows;
    }
  }
  EXPECT_GT(rows_past, 0);
  // what a kill in the middle of an atomic write leaves (the kill above may or may not)
  std::ofstream(killed / ".contacts.pvd.999999.tmp") << "<VTKFile";
  std::ofstream(killed / "snapshots" / ".particles_000005.vtp.999999.tmp") << "<VTKFile";

  const ProcessResult resumed = run_cdpowder("resume " + killed.string() + " --quiet", scratch_);
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("resume from step " + std::to_string(saved.world.step)));
  EXPECT_FALSE(fs::exists(killed / "checkpoint.cdps"));
  fs::remove(killed / ".run.lock");
  fs::remove(whole / ".run.lock");
  expect_same_outputs(whole, killed);
}

// `resume` goes on writing checkpoints at the interval the run was started with
// (checkpoint.toml), so a run killed twice loses at most one interval each time; a finished
// run keeps neither file, and a damaged interval file is refused naming it.
TEST_F(ResumeCli, AResumedRunKeepsItsCheckpointInterval) {
  const fs::path run = scratch_ / "twice";
  // started by SIGKILL once the snapshot `number` is listed (t = 7 number t0)
  const auto run_until_killed = [&](const std::string& command, int number) {
    const fs::path script = scratch_ / "kill.sh";
    std::ofstream(script) << CDPOWDER_EXE << " " << command << " 2>> "
                          << (scratch_ / "twice.log").string() << " &\npid=$!\n"
                          << "for i in $(seq 1 4000); do grep -q particles_00000" << number << " "
                          << (run / "particles.pvd").string()
                          << " 2>/dev/null && break; sleep 0.005; done\n"
                          << "kill -KILL $pid\nwait $pid\n";
    run_process("sh", script.string(), scratch_);
  };
  run_until_killed(
      "compact " + kScene + " --quiet --out " + run.string() + " --checkpoint-every 20", 4);
  ASSERT_TRUE(fs::exists(run / "checkpoint.toml"));
  const double first = cdpowder::load_state(run / "checkpoint.cdps").world.time;
  EXPECT_LT(first, 28.0);
  // killed at t = 49 t0, 9 t0 after its own checkpoint at 40 (no --checkpoint-every given)
  run_until_killed("resume " + run.string() + " --quiet", 7);
  ASSERT_FALSE(fs::exists(run / "summary.json"));
  const double second = cdpowder::load_state(run / "checkpoint.cdps").world.time;
  EXPECT_GE(second, first + 20.0) << "the resumed run wrote no checkpoint of its own";
  EXPECT_LT(second, 49.0);

  std::ofstream(run / "checkpoint.toml") << "every = -1\n";
  const ProcessResult refused = run_cdpowder("resume " + run.string() + " --quiet", scratch_);
  EXPECT_EQ(refused.status, 2);
  EXPECT_THAT(refused.err, HasSubstr("checkpoint.toml: every: expected the one key `every`, a "
                                     "number > 0"));
  // --checkpoint-every given again replaces it; the run ends and keeps neither file
  const ProcessResult resumed =
      run_cdpowder("resume " + run.string() + " --quiet --checkpoint-every 30", scratch_);
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_FALSE(fs::exists(run / "checkpoint.cdps"));
  EXPECT_FALSE(fs::exists(run / "checkpoint.toml"));
}

// Ctrl-C writes a checkpoint beside the interrupted run's outputs; resumed, with an adaptive
// Δt and time cadences (the forced last row and snapshot of the interrupted run go), the run
// ends as the run never stopped.
TEST_F(ResumeCli, ARunStoppedByCtrlCResumesBitIdentically) {
  const std::string scene = kQuick.string() +
                            " --set contact.mu_roll=0.2 --set contact.mu_twist=0.2"
                            " --set solver.adaptive_dt=true --set run.timeseries_interval=0.5"
                            " --set run.snapshot_interval=10 --quiet";
  const fs::path whole = scratch_ / "whole";
  ASSERT_EQ(run_cdpowder("compact " + scene + " --out " + whole.string(), scratch_).status, 0);
  const fs::path stopped = scratch_ / "stopped";
  const fs::path script = scratch_ / "stop.sh";
  std::ofstream(script) << CDPOWDER_EXE << " compact " << scene << " --out " << stopped.string()
                        << " &\npid=$!\nsleep 0.4\nkill -INT $pid\nwait $pid\necho \"exit $?\"\n";
  const ProcessResult r = run_process("sh", script.string(), scratch_);
  EXPECT_THAT(r.out, HasSubstr("exit 1"));
  EXPECT_THAT(r.err, HasSubstr("cdpowder resume " + stopped.string() + " continues it"));
  ASSERT_TRUE(fs::exists(stopped / "checkpoint.cdps"));
  EXPECT_TRUE(physics_of(stopped / "summary.json")["run"]["interrupted"].get<bool>());

  const ProcessResult resumed = run_cdpowder("resume " + stopped.string() + " --quiet", scratch_);
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  fs::remove(stopped / ".run.lock");
  fs::remove(whole / ".run.lock");
  expect_same_outputs(whole, stopped);
}

/// A folder as a run leaves it once stopped after 30 steps (a 1 t0 simulate of the quick
/// scene), with its checkpoint's bytes passed through `edit`.
fs::path stopped_run(const fs::path& folder, const std::function<void(std::string&)>& edit) {
  cdpowder::SceneReadOptions how;
  const cdpowder::Scene scene = cdpowder::read_scene(
      kQuick, {"run.until_blocked=false", "run.duration=1", "run.snapshot_every=0"}, how);
  cdpowder::World world = cdpowder::make_world(scene);
  fs::create_directories(folder);
  std::ofstream(folder / "scene.toml") << scene.effective_toml;
  std::ofstream(folder / "initial_particles.csv")
      << cdpowder::particles_csv(world.bodies, cdpowder::provenance_header(scene));
  cdpowder::StepWorkspace work(scene.step.solver.seed);
  cdpowder::RunState state;
  cdpowder::run_simulation(world, work, scene.step, scene.run, state, {},
                           [&] { return state.result.steps == 30; });
  std::string bytes = cdpowder::encode_state(scene.effective_toml, world, work, state);
  edit(bytes);
  // the checksum again, so that only the edit is wrong
  cdpowder::ByteWriter sum;
  sum.u64(cdpowder::fnv1a64(std::string_view(bytes).substr(0, bytes.size() - 8)));
  bytes.replace(bytes.size() - 8, 8, sum.bytes());
  std::ofstream(folder / "checkpoint.cdps", std::ios::binary) << bytes;
  return folder;
}

// A checkpoint of another format is refused, naming both formats; nothing is written.
TEST_F(ResumeCli, ACheckpointOfAnotherFormatIsRefusedNamingBothFormats) {
  const fs::path run = stopped_run(scratch_ / "run", [](std::string& bytes) {
    cdpowder::ByteWriter version;
    version.u32(999);
    bytes.replace(8, 4, version.bytes());
  });
  const ProcessResult r = run_cdpowder("resume " + run.string(), scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("state format 999; this build of cdpowder reads formats 1 to " +
                               std::to_string(cdpowder::kStateFormatVersion)));
  EXPECT_FALSE(fs::exists(run / "summary.json"));
}

// Another build of the same format goes on, with a warning that the result will not be
// bit-identical; its outputs are written as usual.
TEST_F(ResumeCli, ACheckpointOfAnotherBuildResumesWithAWarning) {
  const fs::path run = stopped_run(scratch_ / "run", [](std::string& bytes) {
    // magic (8), format (4), version (length + text), commit (length + text)
    cdpowder::ByteReader in(std::string_view(bytes).substr(12), "memory");
    const std::string version = in.string();
    const std::size_t commit_at = 12 + 8 + version.size();
    cdpowder::ByteReader commit_in(std::string_view(bytes).substr(commit_at), "memory");
    const std::string commit = commit_in.string();
    cdpowder::ByteWriter other;
    other.string("0123abc");
    bytes.replace(commit_at, 8 + commit.size(), other.bytes());
  });
  const ProcessResult r = run_cdpowder("resume " + run.string() + " --quiet", scratch_);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("(commit 0123abc)"));
  EXPECT_THAT(r.err, HasSubstr("will not be bit-identical"));
  EXPECT_TRUE(fs::exists(run / "summary.json"));
  EXPECT_FALSE(fs::exists(run / "checkpoint.cdps"));
}

// Without its starting packing a run cannot go on; this once blamed `--particles`, an
// option resume does not have
TEST_F(ResumeCli, AFolderWithoutItsStartingPackingIsRefused) {
  const fs::path run = stopped_run(scratch_ / "run", [](std::string&) {});
  fs::remove(run / "initial_particles.csv");
  const ProcessResult r = run_cdpowder("resume " + run.string() + " --quiet", scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("initial_particles.csv is missing: the run's starting packing"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("--particles")));
  EXPECT_TRUE(fs::exists(run / "checkpoint.cdps"));
}

TEST_F(ResumeCli, AFolderWithoutACheckpointIsRefused) {
  fs::create_directories(scratch_ / "empty");
  const ProcessResult r = run_cdpowder("resume " + (scratch_ / "empty").string(), scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("no checkpoint.cdps to continue from"));
}

TEST_F(ResumeCli, ACheckpointIntervalMustBeAPositiveTime) {
  for (const char* bad : {"0", "-5", "abc", "inf", "1e400", "5x"}) {
    const ProcessResult r =
        run_cdpowder("simulate " + kQuick.string() + " --out " + (scratch_ / "out").string() +
                         " --checkpoint-every " + bad,
                     scratch_);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_THAT(r.err, HasSubstr(std::string("--checkpoint-every: got '") + bad +
                                 "', expected a simulated time in t0 > 0"));
    EXPECT_FALSE(fs::exists(scratch_ / "out" / "scene.toml")) << bad;
  }
}

// An interval far below Δt (or one rounding onto the step's own time) checkpoints after
// every step; it once stopped the loop again and again without a step (the run hung).
TEST_F(ResumeCli, AnIntervalBelowTheTimeStepCheckpointsEveryStep) {
  for (const char* tiny : {"1e-300", "1e-5"}) {
    const ProcessResult r = run_cdpowder(
        "simulate " + kQuick.string() + " --set run.until_blocked=false --set run.duration=0.5 " +
            "-q --out " + (scratch_ / "out").string() + " --checkpoint-every " + tiny,
        scratch_);
    EXPECT_EQ(r.status, 0) << tiny << ": " << r.err;
    EXPECT_THAT(r.out, HasSubstr("steps=50 ")) << tiny;
  }
}

// Checkpoints change no result, and a finished run keeps none.
TEST_F(ResumeCli, CheckpointsChangeNothingAndAFinishedRunKeepsNone) {
  const std::string scene =
      "simulate " + kQuick.string() + " --set run.until_blocked=false --set run.duration=3 -q";
  ASSERT_EQ(run_cdpowder(scene + " --out " + (scratch_ / "plain").string(), scratch_).status, 0);
  ASSERT_EQ(
      run_cdpowder(scene + " --checkpoint-every 0.05 --out " + (scratch_ / "cp").string(), scratch_)
          .status,
      0);
  EXPECT_FALSE(fs::exists(scratch_ / "cp" / "checkpoint.cdps"));
  expect_same_outputs(scratch_ / "plain", scratch_ / "cp");
}

/// How a program ended after a SIGINT: seconds from the signal to its end, its exit status,
/// and the script's line they were read from.
struct Stopped {
  double seconds = 99.0;
  int status = -1;
  std::string line;
};

/// Sends SIGINT `after` seconds into `command` and measures how the program ends.
Stopped time_to_stop(const std::string& command, double after, const fs::path& scratch) {
  const fs::path script = scratch / "stop.sh";
  std::ofstream(script) << CDPOWDER_EXE << " " << command << " >/dev/null 2>&1 &\npid=$!\nsleep "
                        << after << "\nstart=$(date +%s.%N)\nkill -INT $pid\nwait $pid\nstatus=$?\n"
                        << "echo \"$(echo \"$(date +%s.%N) - $start\" | bc) $status\"\n";
  Stopped stopped;
  stopped.line = run_process("sh", script.string(), scratch).out;
  std::istringstream in(stopped.line);
  in >> stopped.seconds >> stopped.status;
  return stopped;
}

// Ctrl-C inside a final static solve of 10⁸ sweeps (minutes) ends it within a second, on a
// sweep's output; the run is interrupted with a checkpoint. The solve runs with the scalar
// kernel: the coloured one reaches the exact fixed point of this packing (every change 0.0)
// after ≈ 57 000 sweeps and so meets even a tolerance of 1e-300 in under a second.
TEST_F(ResumeCli, CtrlCInsideALongStaticSolveIsHonouredWithinASecond) {
  const fs::path out = scratch_ / "out";
  const Stopped stop = time_to_stop(
      "compact " + kQuick.string() +
          " --set run.blocked.final_tolerance=1e-300 --set run.blocked.final_max_passes=100000000"
          " --set solver.kernel='\"scalar\"' --quiet --out " +
          out.string(),
      1.5, scratch_);
  EXPECT_LT(stop.seconds, 1.0) << stop.line;
  EXPECT_EQ(stop.status, 1) << stop.line;
  EXPECT_TRUE(fs::exists(out / "checkpoint.cdps"));
  EXPECT_TRUE(physics_of(out / "summary.json")["run"]["interrupted"].get<bool>());
}

// Ctrl-C inside one step of 10⁸ sweeps ends it within a second; the step is abandoned, so
// the checkpoint holds the state before it.
TEST_F(ResumeCli, CtrlCInsideALongStepIsHonouredWithinASecond) {
  const fs::path out = scratch_ / "out";
  const Stopped stop =
      time_to_stop("compact " + kQuick.string() +
                       " --set solver.tolerance=1e-300 --set solver.max_passes=100000000"
                       " --quiet --out " +
                       out.string(),
                   0.5, scratch_);
  EXPECT_LT(stop.seconds, 1.0) << stop.line;
  EXPECT_EQ(stop.status, 1) << stop.line;
  ASSERT_TRUE(fs::exists(out / "checkpoint.cdps"));
  EXPECT_EQ(cdpowder::load_state(out / "checkpoint.cdps").world.step, 0);
}

// A sweep stopped by Ctrl-C (its run gets SIGTERM and writes a checkpoint) continues the run
// from its checkpoint when started again, and tabulates what a sweep never stopped does.
TEST_F(ResumeCli, AnInterruptedSweepContinuesItsRunFromTheCheckpoint) {
  const fs::path sweep = scratch_ / "sweep.toml";
  std::ofstream(sweep) << "scene = \"" << kQuick.string() << "\"\nseeds = 1\n"
                       << "set = [\"contact.mu_roll=0.2\", \"contact.mu_twist=0.2\"]\n";
  const fs::path whole = scratch_ / "whole";
  ASSERT_EQ(
      run_cdpowder("sweep " + sweep.string() + " -q -j 1 --out " + whole.string(), scratch_).status,
      0);
  const fs::path out = scratch_ / "stopped";
  const fs::path run = out / "runs" / "base" / "seed_1";
  const fs::path script = scratch_ / "stop.sh";
  std::ofstream(script) << CDPOWDER_EXE << " sweep " << sweep.string() << " -q -j 1 --out "
                        << out.string() << " --checkpoint-every 20 &\npid=$!\n"
                        << "for i in $(seq 1 2000); do [ -f " << (run / "checkpoint.cdps").string()
                        << " ] && break; sleep 0.005; done\nkill -INT $pid\nwait $pid\n";
  run_process("sh", script.string(), scratch_);
  ASSERT_TRUE(fs::exists(run / "checkpoint.cdps"));
  const ProcessResult dry =
      run_cdpowder("sweep " + sweep.string() + " --dry-run --out " + out.string(), scratch_);
  EXPECT_THAT(dry.out, HasSubstr("resume   runs/base/seed_1"));
  const ProcessResult list = run_cdpowder(
      "sweep " + sweep.string() + " --list --checkpoint-every 20 --out " + out.string(), scratch_);
  EXPECT_THAT(list.out, HasSubstr("--checkpoint-every 20 --task 0"));

  const ProcessResult again =
      run_cdpowder("sweep " + sweep.string() + " -q -j 1 --out " + out.string(), scratch_);
  EXPECT_EQ(again.status, 0) << again.err;
  const std::string log = slurp(run / "log.txt");
  EXPECT_THAT(log, HasSubstr(": compact "));  // the first attempt's lines are kept
  EXPECT_THAT(log, HasSubstr(": resume from step "));
  EXPECT_EQ(physics_of(run / "summary.json"),
            physics_of(whole / "runs" / "base" / "seed_1" / "summary.json"));
  EXPECT_TRUE(slurp(run / "particles.csv") ==
              slurp(whole / "runs" / "base" / "seed_1" / "particles.csv"));
}

}  // namespace
