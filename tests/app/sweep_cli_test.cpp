// Tests of `cdpowder sweep`, run as a process: a small grid of short compactions in
// parallel, the tables it writes, the report tool on them, resuming after a lost run, an
// interrupted sweep, a sweep within a time limit, and bad sweep files refused before
// anything is written.
#include "cdpowder/core/cpu_budget.hpp"
#include "support/cli_process.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using cdpowder::testing::ProcessResult;
using cdpowder::testing::run_cdpowder;
using cdpowder::testing::slurp;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kQuick = CDPOWDER_SOURCE_DIR "/examples/quick/scene.toml";
const fs::path kReport = CDPOWDER_SOURCE_DIR "/tools/report.py";

/// Data rows of a CSV (lines not starting with '#', minus the column header).
std::size_t data_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::size_t rows = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') ++rows;
  }
  return rows == 0 ? 0 : rows - 1;
}

using SweepCli = cdpowder::testing::ScratchFolderTest;

/// 2 × 2 grid, 2 seeds, each run 5 t0 of the quick example's compaction (≈ 0.1 s).
fs::path write_short_sweep(const fs::path& folder) {
  fs::path file = folder / "sweep.toml";
  std::ofstream(file) << "scene = \"" << kQuick.string() << "\"\n"
                      << "seeds = 2\nset = [\"run.max_duration=5\"]\n"
                      << "[grid.contact]\nmu_roll = [0.0, 1.0]\nmu_twist = [0.0, 1.0]\n";
  return file;
}

TEST_F(SweepCli, RunsEveryPointAndSeedAndTabulatesThem) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  const ProcessResult r =
      run_cdpowder("sweep " + sweep.string() + " --out " + out.string() + " -j 2", scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("8 of 8 runs finished"));
  EXPECT_THAT(r.err, HasSubstr("[8/8]"));
  EXPECT_EQ(data_rows(out / "results.csv"), 8U);
  EXPECT_EQ(data_rows(out / "points.csv"), 4U);
  EXPECT_TRUE(fs::exists(out / "sweep.toml"));
  const fs::path run = out / "runs" / "contact.mu_roll=1.0,contact.mu_twist=0.0" / "seed_2";
  const nlohmann::json s = nlohmann::json::parse(slurp(run / "summary.json"));
  EXPECT_EQ(s["scene"]["contact"]["mu_roll"], 1.0);
  EXPECT_EQ(s["scene"]["contact"]["mu_twist"], 0.0);
  EXPECT_EQ(s["scene"]["deposition"]["seed"], 2);
  EXPECT_EQ(s["scene"]["solver"]["seed"], 2);
  // each run is the same as the compact command with the same overrides
  const ProcessResult single =
      run_cdpowder("compact " + kQuick.string() + " --out " + (scratch_ / "single").string() +
                       " --quiet --set run.max_duration=5 --set contact.mu_roll=1.0 "
                       "--set contact.mu_twist=0.0 --set deposition.seed=2 --set solver.seed=2",
                   scratch_);
  ASSERT_EQ(single.status, 4) << single.err;  // kExitNotBlocked: too short to block
  const nlohmann::json alone = nlohmann::json::parse(slurp(scratch_ / "single" / "summary.json"));
  EXPECT_EQ(alone["porosity"], s["porosity"]);
  EXPECT_EQ(alone["run"]["total_passes"], s["run"]["total_passes"]);

  // the report tool turns the folder into figures and tables (these runs are too short to
  // block, so --all-runs)
  const ProcessResult report = cdpowder::testing::run_process(
      "/usr/bin/python3", kReport.string() + " " + out.string() + " --all-runs", scratch_);
  ASSERT_EQ(report.status, 0) << report.err;
  for (const char* name : {"report.md", "fig5_porosity.png", "fig5_porosity.svg",
                           "added_porosity.png", "additivity.png", "packing.png"}) {
    EXPECT_TRUE(fs::exists(out / "report" / name)) << name;
  }
  const std::string md = slurp(out / "report" / "report.md");
  EXPECT_THAT(md, HasSubstr("E0 = E(0, 0)"));
  EXPECT_THAT(md, HasSubstr("## Table 1"));
  EXPECT_THAT(md, HasSubstr("8 finished runs, 0 blocked"));
}

// command = "simulate": each run is `cdpowder simulate`, for the scene's own duration (no
// piston demanded, no blocked state)
TEST_F(SweepCli, ASweepOfSimulationsRunsSimulate) {
  const fs::path sweep = scratch_ / "simulate.toml";
  std::ofstream(sweep) << "scene = \"" << kQuick.string() << "\"\ncommand = \"simulate\"\n"
                       << "seeds = 1\nset = [\"run.until_blocked=false\", \"run.duration=1\"]\n"
                       << "[grid.contact]\nmu = [0.1, 0.5]\n";
  const fs::path out = scratch_ / "out";
  const ProcessResult r =
      run_cdpowder("sweep " + sweep.string() + " --out " + out.string(), scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("2 of 2 runs finished"));
  const fs::path run = out / "runs" / "contact.mu=0.5" / "seed_1";
  EXPECT_THAT(slurp(run / "log.txt"), HasSubstr("simulate "));
  const nlohmann::json s = nlohmann::json::parse(slurp(run / "summary.json"));
  EXPECT_FALSE(s["run"]["until_blocked"].get<bool>());
}

// Runs of a sweep share the cores: with -j 2 on a machine of C cores each run's solve may use
// C / 2 of them (at least one), said in its log; the same runs one at a time may use all.
TEST_F(SweepCli, RunsAtOnceShareTheCores) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  ASSERT_EQ(run_cdpowder("sweep " + sweep.string() + " --out " + out.string() +
                             " -j 2 --quiet --set solver.threads=0",
                         scratch_)
                .status,
            0);
  const std::string log =
      slurp(out / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / "seed_1" / "log.txt");
  const int share = std::max(1, std::min(2, cdpowder::usable_cores() / 2));
  EXPECT_THAT(log, HasSubstr(fmt::format(", {} thread{}", share, share == 1 ? "" : "s"))) << log;
}

TEST_F(SweepCli, RestartRunsOnlyWhatIsMissing) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  const std::string command = "sweep " + sweep.string() + " --out " + out.string() + " -j 2";
  ASSERT_EQ(run_cdpowder(command, scratch_).status, 0);
  const fs::path lost = out / "runs" / "contact.mu_roll=0.0,contact.mu_twist=1.0" / "seed_1";
  fs::remove(lost / "summary.json");
  const ProcessResult again = run_cdpowder(command, scratch_);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("7 already finished"));
  EXPECT_TRUE(fs::exists(lost / "summary.json"));
  EXPECT_EQ(data_rows(out / "results.csv"), 8U);
  // a changed fixed override changes every run's scene: nothing is reused
  const ProcessResult changed =
      run_cdpowder(command + " --dry-run --set solver.tolerance=1e-5", scratch_);
  EXPECT_THAT(changed.out, HasSubstr("0 finished, 0 reused, 8 to run"));
}

// A run with its summary but without every output (killed while a build that wrote the
// summary first was writing the rest) is not finished: --dry-run and --collect say it is
// incomplete, and the sweep runs it again.
TEST_F(SweepCli, ARunWithASummaryButMissingOutputsIsRunAgain) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  const std::string command = "sweep " + sweep.string() + " --out " + out.string() + " -j 2";
  ASSERT_EQ(run_cdpowder(command, scratch_).status, 0);
  const fs::path cut = out / "runs" / "contact.mu_roll=1.0,contact.mu_twist=0.0" / "seed_2";
  fs::remove(cut / "particles.csv");
  fs::remove(cut / "timeseries.csv");
  const ProcessResult dry = run_cdpowder(command + " --dry-run", scratch_);
  EXPECT_THAT(dry.out, HasSubstr("7 finished, 0 reused, 1 to run"));
  EXPECT_THAT(dry.out, HasSubstr("(incomplete: particles.csv, timeseries.csv missing)"));
  const ProcessResult collect = run_cdpowder(command + " --collect", scratch_);
  EXPECT_THAT(collect.out, HasSubstr("7 of 8 runs finished"));
  EXPECT_THAT(collect.out, HasSubstr("is incomplete (particles.csv, timeseries.csv missing)"));
  const ProcessResult again = run_cdpowder(command, scratch_);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("7 already finished"));
  EXPECT_TRUE(fs::exists(cut / "particles.csv"));
  EXPECT_TRUE(fs::exists(cut / "timeseries.csv"));
  EXPECT_EQ(data_rows(out / "results.csv"), 8U);
}

// A run that cannot write its outputs (here a file-size limit: a full disk fails the same
// way, measured on a 3 MB tmpfs, docs/sweeps.md) exits with its own status, and the sweep
// starts no further run, which would fail alike; the same command goes on once it can write.
TEST_F(SweepCli, AWriteErrorStopsStartingRunsAndTheSameCommandGoesOn) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  // a row per step: the time series (≈ 0.1 MB) outgrows a 64-block limit (32 or 64 kB)
  const std::string command =
      "sweep " + sweep.string() + " --out " + out.string() + " -j 1 --set run.timeseries_every=1";
  const fs::path script = scratch_ / "limited.sh";
  std::ofstream(script) << "ulimit -f 64\nexec " << CDPOWDER_EXE << " " << command << "\n";
  const ProcessResult limited = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(limited.status, 5) << limited.err;
  // its time series failed at its end: its summary keeps its results, but the folder lacks an
  // output, so the run is not finished and runs again
  EXPECT_THAT(limited.err, HasSubstr("seed 1: FAILED (could not write its outputs)"));
  const fs::path first = out / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / "seed_1";
  EXPECT_TRUE(fs::exists(first / "summary.json"));
  EXPECT_FALSE(fs::exists(first / "timeseries.csv"));
  EXPECT_THAT(limited.out, HasSubstr("sweep: 0 of 8 runs finished, 1 failed"));
  EXPECT_THAT(limited.out, HasSubstr("stopped starting runs after a write error (cannot write "));
  EXPECT_THAT(limited.out, HasSubstr("timeseries.csv: File too large)"));
  EXPECT_THAT(limited.out, HasSubstr("7 not started"));
  std::size_t started = 0;
  for (const auto& point : fs::directory_iterator(out / "runs")) {
    for ([[maybe_unused]] const auto& run : fs::directory_iterator(point.path())) ++started;
  }
  EXPECT_EQ(started, 1U);

  const ProcessResult again = run_cdpowder(command, scratch_);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_THAT(again.err, HasSubstr("0 already finished"));
  EXPECT_EQ(data_rows(out / "results.csv"), 8U);
}

// A negative or non-numeric count is named as such (once: a 310-digit bound, and an
// unsigned -1 shown as 18446744073709551615)
TEST_F(SweepCli, ABadJobsOrTaskIsNamedWithWhatIsAllowed) {
  const std::string command =
      "sweep " + write_short_sweep(scratch_).string() + " --out " + (scratch_ / "out").string();
  const ProcessResult jobs = run_cdpowder(command + " -j -1", scratch_);
  EXPECT_EQ(jobs.status, 2);
  EXPECT_THAT(jobs.err, HasSubstr("--jobs: got '-1', expected runs at a time, e.g. 2"));
  const ProcessResult letters = run_cdpowder(command + " -j abc", scratch_);
  EXPECT_THAT(letters.err, HasSubstr("--jobs: got 'abc', expected runs at a time"));
  const ProcessResult task = run_cdpowder(command + " --task -1", scratch_);
  EXPECT_EQ(task.status, 2);
  EXPECT_THAT(task.err, HasSubstr("--task: got '-1', expected a run index ≥ 0"));
  // named as every other mistake is: "error: " first
  const ProcessResult abc = run_cdpowder(command + " --task abc", scratch_);
  EXPECT_EQ(abc.status, 2);
  EXPECT_THAT(abc.err, HasSubstr("error: --task: got 'abc', expected a run index ≥ 0"));
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

TEST_F(SweepCli, ReuseCopiesInRunsOfAnotherSweepWithExactlyTheSameScene) {
  const fs::path first = scratch_ / "first";
  ASSERT_EQ(run_cdpowder("sweep " + write_short_sweep(scratch_).string() + " --out " +
                             first.string() + " -j 2",
                         scratch_)
                .status,
            0);
  // a second sweep: μt ∈ {1.0, 0.5} at μn = 0 (fixed, so its folders are named differently),
  // seeds 1 and 2. (1.0, 0.0) is in the first sweep with both seeds; (0.5, 0.0) is not.
  const fs::path second_file = scratch_ / "second.toml";
  std::ofstream(second_file)
      << "scene = \"" << kQuick.string() << "\"\n"
      << "seeds = 2\nset = [\"run.max_duration=5\", \"contact.mu_twist=0.0\"]\n"
      << "[grid.contact]\nmu_roll = [1.0, 0.5]\n";
  const fs::path second = scratch_ / "second";
  const std::string command = "sweep " + second_file.string() + " --out " + second.string() +
                              " -j 2 --reuse " + first.string();
  const ProcessResult dry = run_cdpowder(command + " --dry-run", scratch_);
  ASSERT_EQ(dry.status, 0) << dry.err;
  EXPECT_THAT(dry.out, HasSubstr("0 finished, 2 reused, 2 to run"));
  EXPECT_FALSE(fs::exists(second));  // a dry run writes nothing
  // an earlier attempt's leftovers in a folder that a reused run takes over
  const fs::path stale = second / "runs" / "contact.mu_roll=1.0" / "seed_1" / "particles.csv";
  fs::create_directories(stale.parent_path());
  std::ofstream(stale) << "not this run's\n";
  const ProcessResult r = run_cdpowder(command, scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("2 already finished (2 of them reused)"));
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_THAT(r.out, HasSubstr("4 of 4 runs finished"));
  EXPECT_EQ(data_rows(second / "results.csv"), 4U);
  for (const char* seed : {"seed_1", "seed_2"}) {
    const fs::path copied = second / "runs" / "contact.mu_roll=1.0" / seed;
    EXPECT_EQ(
        slurp(copied / "summary.json"),
        slurp(first / "runs" / "contact.mu_roll=1.0,contact.mu_twist=0.0" / seed / "summary.json"));
    EXPECT_THAT(slurp(copied / "log.txt"), HasSubstr("reused from"));
    EXPECT_TRUE(fs::exists(second / "runs" / "contact.mu_roll=0.5" / seed / "particles.csv"));
  }
  // a reuse folder that does not exist is refused
  const ProcessResult missing =
      run_cdpowder("sweep " + second_file.string() + " --out " + second.string() + " --reuse " +
                       (scratch_ / "nowhere").string(),
                   scratch_);
  EXPECT_NE(missing.status, 0);
  EXPECT_THAT(missing.err, HasSubstr("nowhere"));
}

TEST_F(SweepCli, InterruptKeepsFinishedResultsAndLeavesTheRestPending) {
  // one long run (the quick example with a piston-speed bound no piston meets, so it cannot
  // block before the signal); SIGTERM once it started
  const fs::path sweep = scratch_ / "sweep.toml";
  std::ofstream(sweep) << "scene = \"" << kQuick.string() << "\"\nseeds = 2\n"
                       << "set = [\"run.blocked.piston_speed=1e-300\"]\n";
  const fs::path out = scratch_ / "out";
  const fs::path started = out / "runs" / "base" / "seed_1" / "scene.toml";
  const fs::path script = scratch_ / "interrupt.sh";
  std::ofstream(script) << CDPOWDER_EXE << " sweep " << sweep.string() << " --out " << out.string()
                        << " -j 1 &\npid=$!\n"
                        << "for i in $(seq 1 1200); do [ -f " << started.string()
                        << " ] && break; sleep 0.05; done\n"
                        << "sleep 0.3\n"
                        // a second sweep into the same folder is refused while the first runs
                        << CDPOWDER_EXE << " sweep " << sweep.string() << " --out " << out.string()
                        << " -j 1 > " << (scratch_ / "second.txt").string() << " 2>&1\n"
                        << "echo \"second exit $?\" >> " << (scratch_ / "second.txt").string()
                        << "\nkill -TERM $pid\nwait $pid\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_THAT(r.out, HasSubstr("interrupted"));
  const std::string second = slurp(scratch_ / "second.txt");
  EXPECT_THAT(second, HasSubstr("in use by another sweep"));
  EXPECT_THAT(second, HasSubstr("second exit 1"));
  EXPECT_EQ(data_rows(out / "results.csv"), 0U);
  const nlohmann::json s =
      nlohmann::json::parse(slurp(out / "runs" / "base" / "seed_1" / "summary.json"));
  EXPECT_TRUE(s["run"]["interrupted"].get<bool>());
  EXPECT_FALSE(fs::exists(out / "runs" / "base" / "seed_2"));  // never started
  const ProcessResult listed =
      run_cdpowder("sweep " + sweep.string() + " --out " + out.string() + " --dry-run", scratch_);
  EXPECT_THAT(listed.out, HasSubstr("0 finished, 0 reused, 2 to run"));
}

/// Processes whose command line mentions `text` (from /proc: no procps needed).
std::size_t processes_mentioning(const std::string& text) {
  std::size_t count = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string command = slurp(entry.path() / "cmdline");  // "" once the process is gone
    if (command.find(text) != std::string::npos && command.find("compact") != std::string::npos) {
      ++count;
    }
  }
  return count;
}

// SIGKILL of a sweep once left its runs running, orphaned, and a restarted sweep ran them
// a second time into the same folders. Now a run ends when its sweep dies (it gets SIGTERM,
// writes its outputs flagged interrupted and exits), and a sweep never starts a run whose
// folder another process still holds.
TEST_F(SweepCli, ASweepKilledWithSigkillLeavesNoRunBehind) {
  const fs::path sweep = scratch_ / "sweep.toml";
  std::ofstream(sweep) << "scene = \"" << kQuick.string() << "\"\nseeds = 2\n"
                       << "set = [\"run.blocked.piston_speed=1e-300\"]\n";
  const fs::path out = scratch_ / "killed";
  const fs::path run = out / "runs" / "base" / "seed_1";
  const fs::path script = scratch_ / "kill.sh";
  std::ofstream(script) << CDPOWDER_EXE << " sweep " << sweep.string() << " --out " << out.string()
                        << " -j 1 &\npid=$!\n"
                        << "for i in $(seq 1 1200); do [ -f " << (run / "scene.toml").string()
                        << " ] && break; sleep 0.05; done\n"
                        << "sleep 0.3\nkill -KILL $pid\n"
                        << "for i in $(seq 1 200); do [ -f " << (run / "summary.json").string()
                        << " ] && break; sleep 0.05; done\nsleep 0.5\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(processes_mentioning(run.string()), 0U);
  const nlohmann::json s = nlohmann::json::parse(slurp(run / "summary.json"));
  EXPECT_TRUE(s["run"]["interrupted"].get<bool>());

  // a run folder still held (here by flock(1), as an earlier process would) is not started
  const fs::path held = scratch_ / "held.sh";
  std::ofstream(held) << "flock " << (run / ".run.lock").string()
                      << " sleep 5 &\nholder=$!\nsleep 0.5\n"
                      << CDPOWDER_EXE << " sweep " << sweep.string() << " --out " << out.string()
                      << " -j 1 --set run.max_duration=1 --quiet\n"
                      << "echo \"exit $?\"\nkill $holder\n";
  const std::string log_before = slurp(run / "log.txt");
  const ProcessResult again = cdpowder::testing::run_process("sh", held.string(), scratch_);
  EXPECT_THAT(again.err, HasSubstr("is still being written by an earlier process"));
  EXPECT_THAT(again.out, HasSubstr("1 run still written by an earlier process"));
  EXPECT_THAT(again.out, HasSubstr("exit 1"));
  EXPECT_EQ(slurp(run / "log.txt"), log_before);  // not started again, its log untouched
}

/// A table's lines without comments and without the column named `drop` (wall times differ
/// from run to run).
std::vector<std::string> table_without(const fs::path& csv, const std::string& drop) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  std::size_t dropped = std::string::npos;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields(1);
    bool quoted = false;  // point names are quoted and hold commas
    for (const char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) {
        fields.emplace_back();
      } else {
        fields.back() += c;
      }
    }
    if (dropped == std::string::npos) {
      dropped =
          static_cast<std::size_t>(std::find(fields.begin(), fields.end(), drop) - fields.begin());
    }
    if (dropped < fields.size()) fields.erase(fields.begin() + static_cast<long>(dropped));
    std::string kept;
    for (const std::string& f : fields) kept += f + ",";
    rows.push_back(kept);
  }
  return rows;
}

// Runners that race on every run (each --task started twice within milliseconds, as a
// requeued array job can be): every run is done once, no runner reports a failure, and no
// log is spliced (the loser takes the lock before it touches the folder, so it writes nothing).
TEST_F(SweepCli, RunnersRacingOnEveryRunDoEachOnceAndNoneFails) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  const fs::path script = scratch_ / "race.sh";
  const std::string task = std::string(CDPOWDER_EXE) + " sweep " + sweep.string() + " --out " +
                           out.string() + " --task ";
  std::ofstream file(script);
  file << "status=0\n";
  for (int i = 0; i < 8; ++i) {
    file << task << i << " 2>>" << (scratch_ / "err.txt").string() << " & p" << i << "a=$!\n"
         << task << i << " 2>>" << (scratch_ / "err.txt").string() << " & p" << i << "b=$!\n";
  }
  for (int i = 0; i < 8; ++i) {
    file << "wait $p" << i << "a || status=1\nwait $p" << i << "b || status=1\n";
  }
  file << "exit $status\n";
  file.close();
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  const std::string err = slurp(scratch_ / "err.txt");
  EXPECT_EQ(r.status, 0) << err;
  EXPECT_THAT(err, Not(HasSubstr("FAILED")));
  std::size_t logs = 0;
  for (const auto& point : fs::directory_iterator(out / "runs")) {
    for (const auto& run : fs::directory_iterator(point.path())) {
      ++logs;
      const std::string log = slurp(run.path() / "log.txt");
      // one run's log: its opening line once
      EXPECT_EQ(log.find("compact "), log.rfind("compact ")) << log;
      EXPECT_TRUE(fs::exists(run.path() / "summary.json")) << run.path();
    }
  }
  EXPECT_EQ(logs, 8U);
  const ProcessResult collect =
      run_cdpowder("sweep " + sweep.string() + " --out " + out.string() + " --collect", scratch_);
  EXPECT_THAT(collect.out, HasSubstr("sweep: 8 of 8 runs finished"));
}

// --list prints a command per run; an outside runner (xargs -P 2 here, GNU parallel or a
// Slurm array elsewhere) runs them in any order; --collect writes the tables: the same as
// those of `cdpowder sweep` itself (wall times aside).
TEST_F(SweepCli, RunsThroughListAndAnOutsideRunnerGiveTheSweepsOwnTables) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path outside = scratch_ / "outside";
  const fs::path script = scratch_ / "runner.sh";
  std::ofstream(script) << CDPOWDER_EXE << " sweep " << sweep.string() << " --out "
                        << outside.string() << " --list > " << (scratch_ / "list.txt").string()
                        << " && xargs -P 2 -I{} sh -c '{}' < " << (scratch_ / "list.txt").string()
                        << " && " << CDPOWDER_EXE << " sweep " << sweep.string() << " --out "
                        << outside.string() << " --collect\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("sweep: 8 of 8 runs finished"));
  const std::string list = slurp(scratch_ / "list.txt");
  EXPECT_THAT(list, HasSubstr("--task 0 --quiet  # run 0: runs/"));
  EXPECT_THAT(list, HasSubstr("--task 7 --quiet  # run 7: runs/"));
  const fs::path own = scratch_ / "own";
  const ProcessResult direct =
      run_cdpowder("sweep " + sweep.string() + " --out " + own.string() + " --quiet", scratch_);
  ASSERT_EQ(direct.status, 0) << direct.err;
  EXPECT_EQ(table_without(outside / "results.csv", "wall_seconds"),
            table_without(own / "results.csv", "wall_seconds"));
  EXPECT_EQ(table_without(outside / "points.csv", ""), table_without(own / "points.csv", ""));
  // a finished run asked for again does nothing; an index outside the plan is refused
  const ProcessResult again = run_cdpowder(
      "sweep " + sweep.string() + " --out " + outside.string() + " --task 3", scratch_);
  EXPECT_EQ(again.status, 0);
  EXPECT_THAT(again.err, HasSubstr("already finished"));
  const ProcessResult beyond = run_cdpowder(
      "sweep " + sweep.string() + " --out " + outside.string() + " --task 8", scratch_);
  EXPECT_EQ(beyond.status, 2);
  EXPECT_THAT(beyond.err, HasSubstr("--task: got 8, expected a run index from 0 to 7"));
}

TEST_F(SweepCli, TimeLimitStartsOnlyRunsExpectedToFinishInTime) {
  const fs::path sweep = write_short_sweep(scratch_);
  const fs::path out = scratch_ / "out";
  const std::string command = "sweep " + sweep.string() + " --out " + out.string() + " -j 2";
  ASSERT_EQ(run_cdpowder(command, scratch_).status, 0);
  // seed 2 of every point is lost, and seed 1 of (0, 0) is recorded as a 100 000 s run:
  // within an hour, that point's seed 2 is not expected to finish, and the runs after it
  // in the sweep's order start in its place
  for (const char* point :
       {"contact.mu_roll=0.0,contact.mu_twist=0.0", "contact.mu_roll=0.0,contact.mu_twist=1.0",
        "contact.mu_roll=1.0,contact.mu_twist=0.0", "contact.mu_roll=1.0,contact.mu_twist=1.0"}) {
    fs::remove(out / "runs" / point / "seed_2" / "summary.json");
  }
  const fs::path slow = out / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / "seed_1";
  nlohmann::json s = nlohmann::json::parse(slurp(slow / "summary.json"));
  s["run"]["wall_seconds"] = 1e5;
  std::ofstream(slow / "summary.json") << s.dump(1);
  const ProcessResult r = run_cdpowder(command + " --time-limit 1h", scratch_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_THAT(r.out, HasSubstr("7 of 8 runs finished; time limit 1:00:00: 1 run left for later"));
  const ProcessResult listed = run_cdpowder(command + " --dry-run", scratch_);
  EXPECT_THAT(listed.out, HasSubstr("7 finished, 0 reused, 1 to run"));
  EXPECT_THAT(listed.out,
              HasSubstr("pending  runs/contact.mu_roll=0.0,contact.mu_twist=0.0/seed_2"));
  // without the limit it runs
  const ProcessResult rest = run_cdpowder(command, scratch_);
  EXPECT_EQ(rest.status, 0) << rest.err;
  EXPECT_THAT(rest.out, HasSubstr("8 of 8 runs finished"));
}

TEST_F(SweepCli, TimeLimitStopsRunsStillGoingAndLeavesThemPending) {
  // a run of unknown length that cannot block (as in the interrupt test) starts, and is
  // stopped at the limit like at a Ctrl-C; the second seed never starts
  const fs::path sweep = scratch_ / "sweep.toml";
  std::ofstream(sweep) << "scene = \"" << kQuick.string() << "\"\nseeds = 2\n"
                       << "set = [\"run.blocked.piston_speed=1e-300\"]\n";
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder(
      "sweep " + sweep.string() + " --out " + out.string() + " -j 1 --time-limit 2s", scratch_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("base seed 1: interrupted"));
  EXPECT_THAT(r.out, HasSubstr("0 of 2 runs finished; time limit 00:02: 2 runs left for later"));
  const nlohmann::json s =
      nlohmann::json::parse(slurp(out / "runs" / "base" / "seed_1" / "summary.json"));
  EXPECT_TRUE(s["run"]["interrupted"].get<bool>());
  EXPECT_FALSE(fs::exists(out / "runs" / "base" / "seed_2"));
  // a limit that is not a duration is refused before anything runs
  const ProcessResult bad = run_cdpowder(
      "sweep " + sweep.string() + " --out " + (scratch_ / "bad").string() + " --time-limit 2x",
      scratch_);
  EXPECT_EQ(bad.status, 2);
  EXPECT_THAT(bad.err, HasSubstr("'2x' is not a positive duration"));
  EXPECT_FALSE(fs::exists(scratch_ / "bad"));
}

TEST_F(SweepCli, BadSweepFilesAreRefusedBeforeAnythingIsWritten) {
  const fs::path out = scratch_ / "out";
  const fs::path typo = scratch_ / "typo.toml";
  std::ofstream(typo) << "scene = \"" << kQuick.string()
                      << "\"\n[grid]\n\"contact.mu_rol\" = [1.0]\n";
  const ProcessResult r =
      run_cdpowder("sweep " + typo.string() + " --out " + out.string(), scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("contact.mu_rol"));
  EXPECT_THAT(r.err, HasSubstr("did you mean"));
  const fs::path range = scratch_ / "range.toml";
  std::ofstream(range) << "scene = \"" << kQuick.string()
                       << "\"\n[grid]\n\"contact.mu\" = [0.3, -1.0]\n";
  const ProcessResult r2 =
      run_cdpowder("sweep " + range.string() + " --out " + out.string(), scratch_);
  EXPECT_EQ(r2.status, 2);
  EXPECT_THAT(r2.err, HasSubstr("contact.mu"));
  const fs::path same = scratch_ / "same.toml";  // 1 and 1.0 are the same scene
  std::ofstream(same) << "scene = \"" << kQuick.string()
                      << "\"\n[grid]\n\"contact.mu_roll\" = [1, 1.0]\n";
  const ProcessResult r3 =
      run_cdpowder("sweep " + same.string() + " --out " + out.string(), scratch_);
  EXPECT_EQ(r3.status, 2);
  EXPECT_THAT(r3.err, HasSubstr("give the same scene"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
