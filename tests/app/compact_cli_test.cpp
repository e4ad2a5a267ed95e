// Tests of the `cdpowder deposit` and `cdpowder compact` commands, run as processes: the
// quick example compacts to the blocked state with σzz equal to the applied pressure, the
// VTK files read back, results are reproducible, a deposit feeds a compaction, and bad
// configurations are refused before anything is written.
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/run/run_summary.hpp"
#include "support/cli_process.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using cdpowder::testing::ProcessResult;
using cdpowder::testing::run_cdpowder;
using cdpowder::testing::slurp;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kQuick = CDPOWDER_SOURCE_DIR "/examples/quick/scene.toml";
const fs::path kPaper = CDPOWDER_SOURCE_DIR "/examples/paper/scene.toml";
const fs::path kCheckVtk = CDPOWDER_SOURCE_DIR "/tests/app/check_vtk.py";

nlohmann::json summary_of(const fs::path& out) {
  return nlohmann::json::parse(slurp(out / "summary.json"));
}

/// The summary without what legitimately differs between identical runs (timings).
nlohmann::json without_timings(nlohmann::json j) {
  j["run"].erase("wall_seconds");
  j["run"].erase("stage_seconds");
  return j;
}

using CompactCli = cdpowder::testing::ScratchFolderTest;

// A short, deterministic piece of the quick example's compaction (it does not block yet, so
// the program exits with kNotBlocked after writing every output).
const std::string kShort = "--quiet --set run.max_duration=5";
constexpr int kNotBlocked = 4;  // app/commands/simulate.hpp, kExitNotBlocked

TEST_F(CompactCli, QuickExampleBlocksWithStressEqualToThePressure) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " + out.string() +
                                           " --quiet --set run.snapshot_every=2000",
                                       scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("blocked=yes"));
  EXPECT_THAT(r.out, HasSubstr("porosity="));
  const nlohmann::json s = summary_of(out);
  EXPECT_EQ(s["schema"].get<int>(), cdpowder::kRunSummarySchema);
  EXPECT_TRUE(s["run"]["blocked"].get<bool>());
  EXPECT_FALSE(s["run"]["interrupted"].get<bool>());
  // the library reads what the command line wrote, field for field
  const cdpowder::RunSummary read = cdpowder::parse_run_summary(slurp(out / "summary.json"));
  EXPECT_EQ(read.porosity, s["porosity"].get<double>());
  EXPECT_EQ(read.run.steps, s["run"]["steps"].get<std::int64_t>());
  EXPECT_EQ(cdpowder::run_summary_json(read), slurp(out / "summary.json"));
  // Blocked: the packing carries the piston. σzz = F/(L_x L_y) (force balance of a slab)
  // within 1 %, and the piston's own balance within the blocked-state threshold 1e-3.
  EXPECT_NEAR(s["stress"]["sigma_zz_over_pressure"].get<double>(), 1.0, 0.01);
  EXPECT_LT(s["piston"]["force_imbalance"].get<double>(), 1e-3);
  // σ = σ⁺ + σ⁻ and the split has the right signs
  const double plus = s["stress"]["sigma_zz_compressive_over_pressure"].get<double>();
  const double minus = s["stress"]["sigma_zz_tensile_over_pressure"].get<double>();
  EXPECT_GE(plus, 0.0);
  EXPECT_LE(minus, 0.0);
  EXPECT_NEAR(plus + minus, s["stress"]["sigma_zz_over_pressure"].get<double>(), 1e-9);
  // the piston compacted the deposit: porosity fell, and stays in the physical range
  EXPECT_LT(s["porosity"].get<double>(), s["initial_porosity"].get<double>());
  EXPECT_GT(s["porosity"].get<double>(), 0.5);
  EXPECT_LT(s["accuracy"]["mean_overlap"].get<double>(), 1e-3);
  EXPECT_GT(s["contacts"]["coordination_number"].get<double>(), 1.0);
  EXPECT_EQ(s["spheres"], 100);
  // where it ran, for reading its timings: the kernel's instruction set in this environment
  EXPECT_EQ(s["program"]["kernel"].get<std::string>(), cdpowder::lanes::kernel_isa_name());
  EXPECT_TRUE(s["program"]["cpu"].is_string());

  for (const char* name : {"summary.json", "particles.csv", "initial_particles.csv", "contacts.csv",
                           "timeseries.csv", "scene.toml", "particles.vtp", "contacts.vtp",
                           "walls.vtp", "particles.pvd", "contacts.pvd", "walls.pvd"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  // ParaView's files, read back by an independent reader and checked against the CSVs
  const ProcessResult vtk =
      cdpowder::testing::run_process("python3", kCheckVtk.string() + " " + out.string(), scratch_);
  EXPECT_EQ(vtk.status, 0) << vtk.err;
  EXPECT_THAT(vtk.out, HasSubstr("valid"));
}

// run.vtk_format = "binary": every .vtp with its arrays as appended base64, read back by the
// same independent reader (which decodes the blocks) and checked against the CSVs.
TEST_F(CompactCli, BinaryVtkFilesReadBackAsTheRunsState) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r =
      run_cdpowder("compact " + kQuick.string() + " --out " + out.string() + " " + kShort +
                       " --set run.vtk_format='\"binary\"' --set run.snapshot_every=100",
                   scratch_);
  ASSERT_EQ(r.status, kNotBlocked) << r.err;
  for (const char* name : {"particles.vtp", "contacts.vtp", "walls.vtp"}) {
    const std::string text = slurp(out / name);
    EXPECT_THAT(text, HasSubstr("format=\"appended\"")) << name;
    EXPECT_THAT(text, HasSubstr("<AppendedData encoding=\"base64\">")) << name;
    EXPECT_THAT(text, Not(HasSubstr("format=\"ascii\""))) << name;
  }
  const ProcessResult vtk =
      cdpowder::testing::run_process("python3", kCheckVtk.string() + " " + out.string(), scratch_);
  EXPECT_EQ(vtk.status, 0) << vtk.err;
  EXPECT_THAT(vtk.out, HasSubstr("valid"));
}

// At the paper example's loose solver settings a resting piston's per-step force balance is
// solver noise of up to a few per cent; the step solved to the final tolerance once blocked
// is what the stress is measured on, so σzz = p holds to that tolerance all the same.
TEST_F(CompactCli, StressIsMeasuredOnAStepSolvedToTheFinalTolerance) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder(
      "compact " + kQuick.string() + " --out " + out.string() +
          " --quiet --set solver.tolerance=1e-3 --set solver.max_passes=200"
          " --set run.blocked.piston_speed=1e-5 --set run.blocked.sphere_speed=1e-2"
          " --set run.blocked.force_balance=1e-2 --set run.blocked.final_tolerance=1e-6",
      scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json s = summary_of(out);
  ASSERT_TRUE(s["run"]["blocked"].get<bool>());
  const nlohmann::json& final_solve = s["accuracy"]["final_solve"];
  ASSERT_TRUE(final_solve.is_object());
  EXPECT_TRUE(final_solve["converged"].get<bool>());
  EXPECT_LE(final_solve["error_estimate"].get<double>(), 1e-6);
  EXPECT_NEAR(s["stress"]["sigma_zz_over_pressure"].get<double>(), 1.0, 1e-3);
  EXPECT_LT(s["piston"]["force_imbalance"].get<double>(), 1e-3);
}

TEST_F(CompactCli, SameSeedGivesIdenticalSummariesAnotherSeedADifferentOne) {
  const auto run = [&](const std::string& name, const std::string& extra) {
    const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " +
                                             (scratch_ / name).string() + " " + kShort + extra,
                                         scratch_);
    EXPECT_EQ(r.status, kNotBlocked) << r.err;
    return without_timings(summary_of(scratch_ / name));
  };
  const nlohmann::json a = run("a", "");
  const nlohmann::json b = run("b", "");
  const nlohmann::json c = run("c", " --set deposition.seed=2");
  EXPECT_EQ(a, b);
  EXPECT_NE(a["porosity"], c["porosity"]);
  EXPECT_EQ(slurp(scratch_ / "a/particles.csv"), slurp(scratch_ / "b/particles.csv"));
}

TEST_F(CompactCli, DepositFeedsACompactionThatStartsFromTheSameSpheres) {
  const ProcessResult d = run_cdpowder(
      "deposit " + kQuick.string() + " --out " + (scratch_ / "deposit").string() + " --quiet",
      scratch_);
  ASSERT_EQ(d.status, 0) << d.err;
  EXPECT_THAT(d.out, HasSubstr("porosity="));
  const nlohmann::json deposit = summary_of(scratch_ / "deposit");
  EXPECT_EQ(deposit["spheres"], 100);

  const ProcessResult from_csv = run_cdpowder(
      "compact " + kQuick.string() + " --out " + (scratch_ / "from_csv").string() +
          " --particles " + (scratch_ / "deposit/particles.csv").string() + " " + kShort,
      scratch_);
  ASSERT_EQ(from_csv.status, kNotBlocked) << from_csv.err;
  const ProcessResult direct = run_cdpowder(
      "compact " + kQuick.string() + " --out " + (scratch_ / "direct").string() + " " + kShort,
      scratch_);
  ASSERT_EQ(direct.status, kNotBlocked) << direct.err;
  const nlohmann::json a = summary_of(scratch_ / "from_csv");
  const nlohmann::json b = summary_of(scratch_ / "direct");
  EXPECT_DOUBLE_EQ(a["initial_porosity"].get<double>(), deposit["porosity"].get<double>());
  EXPECT_DOUBLE_EQ(a["initial_porosity"].get<double>(), b["initial_porosity"].get<double>());
  EXPECT_DOUBLE_EQ(a["porosity"].get<double>(), b["porosity"].get<double>());
}

TEST_F(CompactCli, InterruptWritesEveryOutputFlaggedInterrupted) {
  // SIGINT once the run has started (scene.toml is written just before the first step):
  // the step finishes, then every output is written. No piston is ever that slow
  // (piston_speed 1e-300), so the run cannot end on its own before the signal.
  const fs::path out = scratch_ / "out";
  const fs::path script = scratch_ / "interrupt.sh";
  std::ofstream(script)
      << CDPOWDER_EXE << " compact " << kQuick.string() << " --out " << out.string()
      << " --quiet --set run.max_duration=1e5 --set run.blocked.piston_speed=1e-300 &\n"
      << "pid=$!\n"
      << "for i in $(seq 1 1200); do [ -f " << (out / "scene.toml").string()
      << " ] && break; sleep 0.05; done\n"
      << "sleep 0.5\nkill -INT $pid\nwait $pid\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_THAT(r.out, HasSubstr("interrupted=yes"));
  const nlohmann::json s = summary_of(out);
  EXPECT_TRUE(s["run"]["interrupted"].get<bool>());
  EXPECT_FALSE(s["run"]["blocked"].get<bool>());
  for (const char* name : {"particles.csv", "contacts.csv", "timeseries.csv", "particles.vtp"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
}

// The stop of a supervisor: GNU timeout signals the process and then its group, and a
// scheduler follows SIGINT with SIGTERM. Every signal after the first is part of the same
// request, so the run still writes every output and a checkpoint (exit 1); before, the second
// SIGINT ended the program with nothing but scene.toml and initial_particles.csv.
TEST_F(CompactCli, RepeatedStopSignalsToTheProcessAndItsGroupKeepTheRun) {
  const fs::path out = scratch_ / "out";
  const fs::path script = scratch_ / "stop.sh";
  // set -m: the background job gets a process group of its own, as under timeout
  std::ofstream(script)
      << "set -m\n"
      << CDPOWDER_EXE << " compact " << kQuick.string() << " --out " << out.string()
      << " --quiet --set run.max_duration=1e5 --set run.blocked.piston_speed=1e-300 &\n"
      << "pid=$!\n"
      << "for i in $(seq 1 1200); do [ -f " << (out / "scene.toml").string()
      << " ] && break; sleep 0.05; done\n"
      << "sleep 0.5\nkill -INT $pid\nkill -INT -$pid\nsleep 0.05\nkill -INT $pid\n"
      << "kill -TERM -$pid 2>/dev/null\nwait $pid\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_THAT(r.out, HasSubstr("interrupted=yes"));
  EXPECT_THAT(r.err, HasSubstr("stopping: the run ends after its step"));
  EXPECT_TRUE(summary_of(out)["run"]["interrupted"].get<bool>());
  for (const char* name : {"summary.json", "particles.csv", "contacts.csv", "timeseries.csv",
                           "particles.vtp", "contacts.vtp", "walls.vtp", "checkpoint.cdps"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
}

// Heavy spheres barely move, so the window's tests find them at rest long before they carry
// the push: their static solves stay out of balance, and the run ends not blocked, saying
// why (exit 4). It was reported blocked, with σzz/p = 0.62.
TEST_F(CompactCli, HeavySpheresAtRestButOutOfBalanceAreNotBlocked) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder(
      "compact " + kQuick.string() + " --out " + out.string() + " --quiet --set system.density=1e6",
      scratch_);
  EXPECT_EQ(r.status, kNotBlocked) << r.err;
  EXPECT_THAT(r.out, HasSubstr("blocked=no"));
  EXPECT_THAT(r.err, HasSubstr("the packing came to rest, but its static solve was out of "
                               "balance in 6 blocked windows: a sphere stays out of balance"));
  const nlohmann::json s = summary_of(out);
  EXPECT_FALSE(s["run"]["blocked"].get<bool>());
  EXPECT_THAT(s["run"]["not_blocked"].get<std::string>(), HasSubstr("largest net force"));
}

// Out of memory is named as such, with what the run was doing, its size and the memory held,
// and its own exit status (6); it was "error: std::bad_alloc" with exit 1.
TEST_F(CompactCli, OutOfMemoryIsNamedWithWhatTheRunWasDoing) {
  const fs::path script = scratch_ / "oom.sh";
  std::ofstream(script) << "ulimit -v 400000\nexec " << CDPOWDER_EXE << " compact "
                        << kQuick.string() << " --out " << (scratch_ / "out").string()
                        << " --quiet --set deposition.spheres=5000000 --set system.lx=3000 "
                           "--set system.ly=3000\n";
  const ProcessResult r = cdpowder::testing::run_process("sh", script.string(), scratch_);
  if (r.err.find("Sanitizer") != std::string::npos) {
    GTEST_SKIP() << "a sanitizer's shadow memory does not fit under ulimit -v";
  }
  EXPECT_EQ(r.status, 6) << r.err;
  EXPECT_THAT(r.err, HasSubstr("error: out of memory while depositing the spheres, 5000000 "
                               "spheres, about "));
}

// A reader that closes the pipe early loses the result line, not the run: exit 0, not 141.
TEST_F(CompactCli, AClosedPipeOnTheResultLineIsNoFailure) {
  const fs::path out = scratch_ / "out";
  const fs::path script = scratch_ / "pipe.sh";
  std::ofstream(script) << "set -o pipefail\n"
                        << CDPOWDER_EXE << " compact " << kQuick.string() << " --out "
                        << out.string() << " " << kShort << " | true\necho status=$?\n";
  const ProcessResult r = cdpowder::testing::run_process("bash", script.string(), scratch_);
  // a 5 t0 compaction does not block: exit 4, whatever the pipe did
  EXPECT_THAT(r.out, HasSubstr("status=4")) << r.err;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

// A time series whose line was damaged is refused by name when the run is resumed, instead
// of continuing from the rows before it and dropping the rest without a word.
/// A quick compaction that cannot end by itself, stopped by SIGINT half a second in: an
/// interrupted run in `out` with its checkpoint. Returns the exit status (1).
int interrupted_run(const fs::path& out, const fs::path& scratch, const std::string& extra = "") {
  const fs::path script = scratch / (out.filename().string() + "_interrupt.sh");
  std::ofstream(script)
      << CDPOWDER_EXE << " compact " << kQuick.string() << " --out " << out.string()
      << " --quiet --set run.max_duration=1e5 --set run.blocked.piston_speed=1e-300 " << extra
      << " &\npid=$!\n"
      << "for i in $(seq 1 1200); do [ -f " << (out / "scene.toml").string()
      << " ] && break; sleep 0.05; done\n"
      << "sleep 0.5\nkill -INT $pid\nwait $pid\n";
  return cdpowder::testing::run_process("sh", script.string(), scratch).status;
}

// Another run's starting packing (the same scene, another deposit) in initial_particles.csv
// is refused when the run is resumed: it gave another initial porosity without a word.
TEST_F(CompactCli, ResumeRefusesAnotherRunsStartingPacking) {
  const fs::path a = scratch_ / "a";
  const fs::path b = scratch_ / "b";
  ASSERT_EQ(interrupted_run(a, scratch_), 1);
  ASSERT_EQ(interrupted_run(b, scratch_, "--set deposition.seed=2"), 1);
  fs::copy_file(b / "initial_particles.csv", a / "initial_particles.csv",
                fs::copy_options::overwrite_existing);
  const ProcessResult r = run_cdpowder("resume " + a.string() + " --quiet", scratch_);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("is not the packing this run began with"));
}

// A run from a particles file outside its folder: when that file changed since the run
// began, resume warns and goes on from the folder's own initial_particles.csv (a deposit, made
// again exactly, is refused instead: the test above).
TEST_F(CompactCli, ResumeGoesOnWhenTheOutsideParticlesFileChanged) {
  const fs::path deposit = scratch_ / "deposit";
  ASSERT_EQ(run_cdpowder("deposit " + kQuick.string() + " --out " + deposit.string() + " --quiet",
                         scratch_)
                .status,
            0);
  const fs::path particles = scratch_ / "mine.csv";
  fs::copy_file(deposit / "particles.csv", particles);
  const fs::path out = scratch_ / "out";
  ASSERT_EQ(interrupted_run(out, scratch_, "--particles " + particles.string()), 1);
  std::string text = cdpowder::testing::slurp(particles);
  // the last sphere moved: its y (the third field, after id and x) becomes 50
  const std::size_t line = text.rfind('\n', text.size() - 2) + 1;
  const std::size_t y = text.find(',', text.find(',', line) + 1) + 1;
  text = text.substr(0, y) + "50" + text.substr(text.find(',', y));
  std::ofstream(particles) << text;
  // the run cannot end by itself: stopped half a second into its resume
  const fs::path script = scratch_ / "resume.sh";
  std::ofstream(script) << CDPOWDER_EXE << " resume " << out.string()
                        << " --quiet &\npid=$!\nsleep 0.5\nkill -INT $pid\nwait $pid\n";
  const ProcessResult resumed = cdpowder::testing::run_process("sh", script.string(), scratch_);
  EXPECT_EQ(resumed.status, 1) << resumed.err;  // interrupted, not refused (2)
  EXPECT_THAT(resumed.err, HasSubstr("differs from the particles file the run's scene names"));
}

TEST_F(CompactCli, ResumeRefusesADamagedTimeSeriesLineByName) {
  const fs::path out = scratch_ / "out";
  ASSERT_EQ(interrupted_run(out, scratch_), 1);
  std::string text = cdpowder::testing::slurp(out / "timeseries.csv");
  std::size_t at = 0;
  for (int line = 1; line < 8; ++line) at = text.find('\n', at) + 1;  // the start of line 8
  text.insert(at, "garbage\n");
  std::ofstream(out / "timeseries.csv", std::ios::binary) << text;
  const ProcessResult r = run_cdpowder("resume " + out.string() + " --quiet", scratch_);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("timeseries.csv:8: 'garbage' is not a row of the time series"));
}

TEST_F(CompactCli, PaperExampleCarriesThePapersParameters) {
  const ProcessResult d = run_cdpowder(
      "deposit " + kPaper.string() + " --out " + (scratch_ / "deposit").string(), scratch_);
  ASSERT_EQ(d.status, 0) << d.err;
  const nlohmann::json s = summary_of(scratch_ / "deposit");
  const nlohmann::json& scene = s["scene"];
  EXPECT_EQ(s["spheres"], 1015);
  EXPECT_EQ(scene["system"]["lx"], 25.0);
  EXPECT_EQ(scene["system"]["ly"], 25.0);
  EXPECT_EQ(scene["deposition"]["capture_radius"], 3.0);
  EXPECT_EQ(scene["deposition"]["capture_rule"], "centre_distance");
  EXPECT_EQ(scene["contact"]["mu"], 0.3);
  EXPECT_EQ(scene["contact"]["cohesion_force"], 1.0);
  EXPECT_EQ(scene["piston"]["mass"], 1000.0);
  EXPECT_EQ(scene["piston"]["pressure"], 1.0 / 400.0);
  EXPECT_EQ(scene["system"]["gravity"], nlohmann::json::array({0.0, 0.0, 0.0}));
  // the independent estimate of the initial porosity is 0.926 ± 0.005 over seeds
  EXPECT_NEAR(s["porosity"].get<double>(), 0.926, 0.015);
}

TEST_F(CompactCli, CompactWithoutAPistonIsRefusedAndWritesNothing) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " + out.string() +
                                           " --quiet --set piston.enabled=false",
                                       scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("piston.enabled"));
  EXPECT_THAT(r.err, HasSubstr("compaction needs the piston"));
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CompactCli, DepositWithoutADepositionSectionIsRefusedAndWritesNothing) {
  const fs::path out = scratch_ / "out";
  const fs::path lattice = CDPOWDER_SOURCE_DIR "/examples/lattice/scene.toml";
  const ProcessResult r =
      run_cdpowder("deposit " + lattice.string() + " --out " + out.string(), scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("deposition"));
  EXPECT_THAT(r.err, HasSubstr("[deposition] section"));
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CompactCli, BadDepositionValueNamesTheKeyTheValueAndWhatIsAllowed) {
  const ProcessResult r =
      run_cdpowder("deposit " + kQuick.string() + " --out " + (scratch_ / "out").string() +
                       " --set deposition.capture_radius=1.5",
                   scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("deposition.capture_radius"));
  EXPECT_THAT(r.err, HasSubstr("got 1.5"));
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

TEST_F(CompactCli, MissingParticlesFileIsNamed) {
  const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " +
                                           (scratch_ / "out").string() + " --particles nowhere.csv",
                                       scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("particles.file"));
  EXPECT_THAT(r.err, HasSubstr("nowhere.csv"));
}

// A load far beyond what the contacts can hold: once measured to end with a negative
// porosity and the piston below the wall, "blocked=yes", exit 0. Now the first step's fault
// stops the run: every output is written, the summary names the fault, the state at the
// fault is kept, and the exit status says so.
TEST_F(CompactCli, AnUnphysicalStateStopsTheRunWithItsOwnStatusAndKeepsTheOutputs) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " + out.string() +
                                           " --quiet --set piston.pressure=1e6",
                                       scratch_);
  EXPECT_EQ(r.status, 3) << r.err;  // kExitFault
  EXPECT_THAT(r.err, HasSubstr("the run failed"));
  EXPECT_THAT(r.err, HasSubstr("at step 1"));
  const nlohmann::json s = summary_of(out);
  EXPECT_TRUE(s["run"]["failed"].get<bool>());
  EXPECT_FALSE(s["run"]["blocked"].get<bool>());
  EXPECT_EQ(s["fault"]["step"], 1);
  EXPECT_TRUE(fs::exists(out / "particles.csv"));
  EXPECT_TRUE(fs::exists(out / "failed_state.cdps"));
}

// Values whose physics cannot work are refused before anything is written.
TEST_F(CompactCli, ACaptureRadiusBeyondHalfTheCellAndAStepLongerThanTheRunAreRefused) {
  for (const std::string set : {"deposition.capture_radius=1e10", "solver.dt=1e6"}) {
    const fs::path out = scratch_ / "refused";
    const ProcessResult r = run_cdpowder(
        "compact " + kQuick.string() + " --out " + out.string() + " --quiet --set " + set,
        scratch_);
    EXPECT_EQ(r.status, 2) << set;
    EXPECT_THAT(r.err, HasSubstr(set.substr(0, set.find('='))));
    EXPECT_THAT(r.err, HasSubstr("expected at most"));
    EXPECT_FALSE(fs::exists(out)) << set;
  }
}

// Under gravity the piston's weight is part of its load: the compaction blocks (once it
// never did), and the loads per area on the piston and the bottom wall differ by the
// spheres' weight per area, σzz lying between them.
TEST_F(CompactCli, ACompactionUnderGravityBlocksAndReportsTheLoadsOnBothWalls) {
  const fs::path out = scratch_ / "out";
  const ProcessResult r = run_cdpowder("compact " + kQuick.string() + " --out " + out.string() +
                                           " --quiet --set system.gravity=[0,0,-0.001]",
                                       scratch_);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json s = summary_of(out);
  EXPECT_TRUE(s["run"]["blocked"].get<bool>());
  const double area = 15.0 * 15.0;
  const double top = s["stress"]["piston_load_per_area"].get<double>();
  const double bottom = s["stress"]["bottom_load_per_area"].get<double>();
  EXPECT_NEAR(top * area, s["piston"]["load"].get<double>(), 1e-3);
  const double weight = s["spheres"].get<double>() * 4.0 / 3.0 * 3.141592653589793 * 0.001;
  EXPECT_NEAR((bottom - top) * area, weight, 1e-3);
  const double sigma_zz = s["stress"]["sigma"][2][2].get<double>();
  EXPECT_GT(sigma_zz, top);
  EXPECT_LT(sigma_zz, bottom);
}

TEST_F(CompactCli, AMisspeltCommandIsNamedWithTheCommandsThatExist) {
  const ProcessResult r = run_cdpowder("compcat " + kQuick.string() + " --out x", scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("unknown command 'compcat'; the commands are simulate, compact"));
  const ProcessResult none = run_cdpowder("", scratch_);  // CLI11: "A subcommand is required"
  EXPECT_EQ(none.status, 2);
  EXPECT_THAT(none.err, HasSubstr("a command is required: simulate, compact, resume, deposit"));
}

// --out naming a file (or a path through one) is refused before anything runs
TEST_F(CompactCli, AnOutputFolderThatIsAFileIsRefusedBeforeTheRun) {
  const fs::path file = scratch_ / "a_file";
  std::ofstream(file) << "keep me\n";
  for (const fs::path& out : {file, file / "below"}) {
    const ProcessResult r = run_cdpowder(
        "compact " + kQuick.string() + " --out " + out.string() + " --quiet", scratch_);
    EXPECT_EQ(r.status, 2) << out;
    EXPECT_THAT(r.err, HasSubstr("--out: '" + file.string() + "'"));
    EXPECT_THAT(r.err, HasSubstr("is a file"));
  }
  EXPECT_EQ(slurp(file), "keep me\n");
}

// --out empty, or a link to nowhere: refused with what it is (once the file system's words,
// "cannot create directories: Invalid argument", exit status 1)
TEST_F(CompactCli, AnEmptyOrDanglingOutputFolderIsRefusedBeforeTheRun) {
  const ProcessResult empty =
      run_cdpowder("compact " + kQuick.string() + " --out '' --quiet", scratch_);
  EXPECT_EQ(empty.status, 2);
  EXPECT_THAT(empty.err, HasSubstr("--out: empty; name a folder"));
  const fs::path link = scratch_ / "link";
  fs::create_symlink(scratch_ / "nowhere", link);
  const ProcessResult dangling =
      run_cdpowder("compact " + kQuick.string() + " --out " + link.string() + " --quiet", scratch_);
  EXPECT_EQ(dangling.status, 2);
  EXPECT_THAT(dangling.err, HasSubstr("is a link to '" + (scratch_ / "nowhere").string() +
                                      "', which does not exist"));
}

// A scene kept in the output folder as scene.toml was once replaced by the run's resolved
// scene (its comments lost), and --particles DIR/particles.csv by the run's packing: both
// are refused, and the files stay as they were.
TEST_F(CompactCli, AnInputTheRunWouldOverwriteIsRefused) {
  const fs::path out = scratch_ / "out";
  fs::create_directories(out);
  fs::copy_file(kQuick, out / "scene.toml");
  const std::string scene = slurp(out / "scene.toml");
  const ProcessResult r = run_cdpowder(
      "compact " + (out / "scene.toml").string() + " --out " + out.string() + " --quiet", scratch_);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("the scene file is the output folder's own scene.toml"));
  EXPECT_EQ(slurp(out / "scene.toml"), scene);
  // also through a link kept elsewhere
  fs::create_symlink(out / "scene.toml", scratch_ / "mine.toml");
  const ProcessResult linked = run_cdpowder(
      "compact " + (scratch_ / "mine.toml").string() + " --out " + out.string() + " --quiet",
      scratch_);
  EXPECT_EQ(linked.status, 2);
  EXPECT_EQ(slurp(out / "scene.toml"), scene);
  std::ofstream(out / "particles.csv") << "x,y,z,r\n5,5,1,1\n";
  const ProcessResult p =
      run_cdpowder("compact " + kQuick.string() + " --particles " +
                       (out / "particles.csv").string() + " --out " + out.string() + " --quiet",
                   scratch_);
  EXPECT_EQ(p.status, 2);
  EXPECT_THAT(p.err, HasSubstr("--particles is the output folder's own particles.csv"));
  EXPECT_EQ(slurp(out / "particles.csv"), "x,y,z,r\n5,5,1,1\n");
}

// stderr here is a pipe, as in a log file: no line redrawn with carriage returns
TEST_F(CompactCli, TheProgressLineIsNotRedrawnIntoALog) {
  const ProcessResult r =
      run_cdpowder("compact " + kQuick.string() + " --out " + (scratch_ / "out").string() + " " +
                       "--set run.max_duration=5",
                   scratch_);
  EXPECT_EQ(r.status, kNotBlocked) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
}

// A rerun into a folder replaces the earlier run whole: its snapshots and a killed run's
// temporaries go, files that are not outputs stay
TEST_F(CompactCli, ARerunIntoAFolderLeavesNothingOfTheEarlierRun) {
  const fs::path out = scratch_ / "out";
  const std::string command =
      "compact " + kQuick.string() + " --out " + out.string() + " " + kShort;
  ASSERT_EQ(run_cdpowder(command + " --set run.snapshot_every=100", scratch_).status, kNotBlocked);
  ASSERT_TRUE(fs::exists(out / "snapshots"));
  ASSERT_TRUE(fs::exists(out / "particles.pvd"));
  std::ofstream(out / ".timeseries.csv.12345.tmp") << "left by a killed run\n";
  std::ofstream(out / "notes.txt") << "mine\n";
  ASSERT_EQ(run_cdpowder(command, scratch_).status, kNotBlocked);
  EXPECT_FALSE(fs::exists(out / "snapshots"));
  EXPECT_FALSE(fs::exists(out / "particles.pvd"));
  EXPECT_FALSE(fs::exists(out / ".timeseries.csv.12345.tmp"));
  EXPECT_EQ(slurp(out / "notes.txt"), "mine\n");
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

}  // namespace
