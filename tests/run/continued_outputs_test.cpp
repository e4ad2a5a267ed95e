// What a run continued from a checkpoint does to the outputs of the run before
// (io/timeseries.hpp cut_timeseries, io/atomic_file.hpp, io/cadence.hpp, io/vtk.hpp): rows
// and snapshots after the checkpoint go, the cadences go on as if never stopped.
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/cadence.hpp"
#include "cdpowder/io/timeseries.hpp"
#include "cdpowder/io/vtk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace cdpowder {
namespace {

namespace fs = std::filesystem;

class ContinuedOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cdpowder_continued_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }

  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  static void write(const fs::path& file, const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
  }

  fs::path dir_;
};

const std::string kHeader = "# cdpowder test\n";

/// A time series as TimeseriesWriter writes it, with a row at each of `steps` (time 0.1 per
/// step), and `tail` after it.
std::string series(const std::vector<int>& steps, const std::string& tail = "") {
  std::string text = kHeader +
                     "step,time,piston_height,piston_velocity,porosity,kinetic_energy,passes,"
                     "converged,residual,error_estimate,contacts,closed_contacts,mean_overlap,"
                     "max_overlap,piston_imbalance,max_net_force,max_cohesive_opening_speed,dt\n";
  for (const int s : steps) text += std::to_string(s) + "," + std::to_string(0.1 * s) + ",1\n";
  return text + tail;
}

// Rows before the checkpoint's step stay; its own row and later ones go, and so does a line
// a killed process left half written.
TEST_F(ContinuedOutputs, TheTimeSeriesIsCutBeforeTheCheckpointsStep) {
  const fs::path file = dir_ / "timeseries.csv";
  write(file, series({10, 20, 30, 40}, "50,5.0,1"));
  const TimeseriesCut cut = cut_timeseries(file, 30);
  EXPECT_TRUE(cut.has_header);
  EXPECT_EQ(cut.rows, 2);
  ASSERT_TRUE(cut.last_row_time.has_value());
  EXPECT_EQ(*cut.last_row_time, 0.1 * 20);
  EXPECT_EQ(cut.bytes, series({10, 20}).size());

  const TimeseriesCut cut_short = cut_timeseries(file, 1000);
  EXPECT_EQ(cut_short.rows, 4);  // not the half line
  EXPECT_EQ(cut_short.bytes, series({10, 20, 30, 40}).size());
}

// A whole line that is not a row (an edit, damage) is named, line and text, for the caller to
// refuse: the 705 rows after such a line were dropped without a word before.
TEST_F(ContinuedOutputs, ALineThatIsNotARowIsNamedNotDropped) {
  const fs::path file = dir_ / "timeseries.csv";
  write(file, series({10, 20}) + "garbage\n" + "30,3.0,1\n");
  const TimeseriesCut cut = cut_timeseries(file, 1000);
  EXPECT_EQ(cut.rows, 2);
  EXPECT_EQ(cut.bad_line, 5);  // the comment, the columns, two rows, then it
  EXPECT_EQ(cut.bad_text, "garbage");
  EXPECT_EQ(cut_timeseries(dir_ / "timeseries.csv", 15).bad_line, 0);  // cut before it
}

// A run written before column 7 was renamed (`sweeps`, now `passes`) continues its file.
TEST_F(ContinuedOutputs, AFileWithTheFormerColumnNamesContinues) {
  const fs::path file = dir_ / "timeseries.csv";
  std::string text = series({10, 20, 30});
  text.replace(text.find("passes,"), 7, "sweeps,");
  write(file, text);
  const TimeseriesCut cut = cut_timeseries(file, 30);
  EXPECT_TRUE(cut.has_header);
  EXPECT_EQ(cut.rows, 2);
}

// A file with nothing but a half header (killed at once) has no header to continue.
TEST_F(ContinuedOutputs, AFileWithoutItsColumnsHasNoHeader) {
  const fs::path file = dir_ / "timeseries.csv";
  write(file, kHeader + "step,time,pis");
  EXPECT_FALSE(cut_timeseries(file, 10).has_header);
}

// The continued stream takes over the earlier file under its own temporary name, cut where
// asked, and appends; the earlier name is gone.
TEST_F(ContinuedOutputs, AStreamContinuesAnEarlierFileCutBack) {
  const fs::path earlier = dir_ / ".timeseries.csv.1.tmp";
  write(earlier, "keep this|drop this");
  {
    AtomicFileStream stream(dir_ / "timeseries.csv", earlier, 10);
    EXPECT_FALSE(fs::exists(earlier));
    stream.write("and this\n");
    stream.flush();
    EXPECT_EQ(read(stream.temporary()), "keep this|and this\n");
    stream.commit();
  }
  EXPECT_EQ(read(dir_ / "timeseries.csv"), "keep this|and this\n");
}

// A time cadence continued after a record at t is due where the one never stopped is.
TEST(ContinuedCadence, ATimeCadenceResumedAfterARecordIsDueWhereTheUnbrokenOneIs) {
  const std::vector<double> steps = {0.2, 0.2, 0.2, 0.3, 0.7, 0.05, 0.05, 0.1, 0.4, 0.3};
  Cadence whole(0, 0.5);
  World world;
  std::vector<std::int64_t> due;
  std::vector<double> times;
  for (const double dt : steps) {
    world.time += dt;
    ++world.step;
    times.push_back(world.time);
    if (whole.due(world)) due.push_back(world.step);
  }
  // times 0.2 0.4 0.6 0.9 1.6 1.65 1.7 1.8 2.2 2.5: due at 0.2, 0.6, 1.6, 2.2 and 2.5
  ASSERT_EQ(due.size(), 5U);
  // stopped after each step; resumed from the time of the last record before
  for (std::int64_t stop_after = 1; std::cmp_less(stop_after, steps.size()); ++stop_after) {
    double last = -1.0;
    for (std::size_t k = 0; std::cmp_less(k, stop_after); ++k) {
      if (std::find(due.begin(), due.end(), static_cast<std::int64_t>(k + 1)) != due.end()) {
        last = times[k];
      }
    }
    Cadence resumed(0, 0.5);
    if (last >= 0.0) resumed.resume_after(last);
    std::vector<std::int64_t> due_after;
    World w;
    for (auto k = static_cast<std::size_t>(stop_after); k < steps.size(); ++k) {
      w.time = times[k];
      w.step = static_cast<std::int64_t>(k + 1);
      if (resumed.due(w)) due_after.push_back(w.step);
    }
    std::vector<std::int64_t> expected;
    for (const std::int64_t s : due) {
      if (s > stop_after) expected.push_back(s);
    }
    EXPECT_EQ(due_after, expected) << "stopped after step " << stop_after;
  }
}

// The snapshots of the run before are read back from the collection with their exact times,
// and those after the checkpoint are removed with their files (also files beyond the
// collection, written by a process killed before it rewrote the collection).
TEST_F(ContinuedOutputs, SnapshotsAfterTheCheckpointAreRemoved) {
  World world;
  const Contacts contacts;
  {
    VtkSnapshotSeries series(dir_);
    for (const double t : {0.0, 0.1 + 0.2, 1.0 / 3.0, 2.5}) {
      world.time = t;
      series.write(world, contacts);
    }
  }
  write(dir_ / "snapshots" / "particles_000004.vtp", "half");  // beyond the collection
  VtkSnapshotSeries continued(dir_);
  const std::vector<double> times = continued.read_earlier();
  ASSERT_EQ(times.size(), 4U);
  EXPECT_EQ(times[1], 0.1 + 0.2);  // the bits, not 9 digits
  EXPECT_EQ(times[2], 1.0 / 3.0);
  continued.keep_earlier(2);
  EXPECT_TRUE(fs::exists(dir_ / "snapshots" / "particles_000001.vtp"));
  EXPECT_TRUE(fs::exists(dir_ / "snapshots" / "contacts_000001.vtp"));
  EXPECT_FALSE(fs::exists(dir_ / "snapshots" / "particles_000002.vtp"));
  EXPECT_FALSE(fs::exists(dir_ / "snapshots" / "contacts_000003.vtp"));
  EXPECT_FALSE(fs::exists(dir_ / "snapshots" / "particles_000004.vtp"));
  world.time = 0.5;
  continued.write(world, contacts);  // numbered on from the kept ones
  EXPECT_TRUE(fs::exists(dir_ / "snapshots" / "particles_000002.vtp"));
  VtkSnapshotSeries again(dir_);
  EXPECT_EQ(again.read_earlier(), (std::vector<double>{0.0, 0.1 + 0.2, 0.5}));
}

}  // namespace
}  // namespace cdpowder
