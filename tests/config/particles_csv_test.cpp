// Tests for src/cdpowder/config/particles_csv.cpp: columns by name, skipped lines, every
// CSV mistake named with file, line and column, and the cell-width check.
#include "cdpowder/config/particles_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace cdpowder {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

/// A fresh directory for the CSV files of one test, removed at its end.
class ParticlesCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cdpowder_particles_csv_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
  }

  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& text) {
    fs::path file = dir_ / "p.csv";
    std::ofstream(file) << text;
    return file;
  }

  /// The formatted issues of a CSV text that must fail to read; bodies must stay untouched.
  std::vector<std::string> issues(const std::string& text) {
    std::vector<std::string> result;
    Bodies bodies;
    try {
      read_particles_csv(write(text), 1.0, bodies);
      ADD_FAILURE() << "no ConfigError for:\n" << text;
    } catch (const ConfigError& error) {
      for (const ConfigIssue& issue : error.issues()) {
        result.push_back(format(issue));
      }
    }
    EXPECT_EQ(bodies.size(), 0U);
    return result;
  }

  fs::path dir_;
};

TEST_F(ParticlesCsv, ReadsColumnsByNameInAnyOrderSkippingCommentsAndBlanks) {
  const fs::path file = write(
      "# written by cdpowder\n"
      "r, z,x,y,vx,wz,fy,tz,fixed\n"
      "\n"
      "1.0,2,3,4,0.5,-1,2e-3,7,0\n"
      "# a comment between rows\n"
      "0.5,1,0,0,0,0,0,0,true\r\n");
  constexpr double kDensity = 2.0;
  Bodies bodies;
  read_particles_csv(file, kDensity, bodies);
  ASSERT_EQ(bodies.size(), 2U);
  EXPECT_EQ(bodies.position[0], Vec3(3.0, 4.0, 2.0));
  EXPECT_EQ(bodies.radius[0], 1.0);
  EXPECT_EQ(bodies.velocity[0], Vec3(0.5, 0.0, 0.0));
  EXPECT_EQ(bodies.angular_velocity[0], Vec3(0.0, 0.0, -1.0));
  EXPECT_EQ(bodies.external_force[0], Vec3(0.0, 2e-3, 0.0));
  EXPECT_EQ(bodies.external_torque[0], Vec3(0.0, 0.0, 7.0));
  EXPECT_DOUBLE_EQ(bodies.mass(0), kDensity * 4.0 / 3.0 * std::numbers::pi);
  EXPECT_EQ(bodies.fixed[0], 0);
  EXPECT_EQ(bodies.fixed[1], 1);
  EXPECT_EQ(bodies.inverse_mass[1], 0.0);
}

TEST_F(ParticlesCsv, AppendsToExistingBodies) {
  Bodies bodies;
  bodies.add_sphere(Vec3::Zero(), 1.0, 1.0);
  read_particles_csv(write("x,y,z,r\n5,5,5,2\n"), 1.0, bodies);
  ASSERT_EQ(bodies.size(), 2U);
  EXPECT_EQ(bodies.radius[1], 2.0);
}

TEST_F(ParticlesCsv, ReportsMissingRequiredColumn) {
  const auto found = issues("# header\nx,y,r\n1,2,3\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0], (dir_ / "p.csv").string() + ":2: z: missing required column (x, y, z, r)");
}

TEST_F(ParticlesCsv, ReportsUnknownAndDuplicateColumns) {
  const auto found = issues("x,y,z,r,vxx,x\n1,2,3,1,0,1\n");
  ASSERT_EQ(found.size(), 2U);
  EXPECT_THAT(found[0], AllOf(HasSubstr(":1: vxx: unknown column"), HasSubstr("'vx'")));
  EXPECT_THAT(found[1], HasSubstr(":1: x: column appears twice"));
}

// spreadsheets begin a UTF-8 CSV with a byte order mark; it is not part of the first name
// "x,y,z,r," once gave "unknown column; did you mean 'x'?" for the empty fifth name
TEST_F(ParticlesCsv, ReportsAColumnWithoutAName) {
  const auto found = issues("x,y,z,r,\n1,1,1,1,\n");
  ASSERT_FALSE(found.empty());
  EXPECT_THAT(found[0], HasSubstr("column 5 of the header has no name (a trailing or doubled "
                                  "comma?)"));
}

TEST_F(ParticlesCsv, ReadsAFileThatBeginsWithAByteOrderMark) {
  Bodies bodies;
  read_particles_csv(write("\xEF\xBB\xBFid,x,y,z,r\n0,1,2,3,1\n"), 1.0, bodies);
  ASSERT_EQ(bodies.size(), 1U);
  EXPECT_DOUBLE_EQ(bodies.position[0].z(), 3.0);
}

TEST_F(ParticlesCsv, EchoesAtMostFortyCharactersOfABadField) {
  const auto found = issues("x,y,z,r\n1,2," + std::string(100000, 'a') + ",1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr("'" + std::string(40, 'a') + "… (100000 characters)'"));
  EXPECT_LT(found[0].size(), 200U);
}

TEST_F(ParticlesCsv, ReportsBadNumberWithLineAndColumn) {
  const auto found = issues("x,y,z,r\n1,2,3,1\n1,2,abc,1\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], AllOf(HasSubstr("p.csv:3: z:"), HasSubstr("'abc'")));
}

TEST_F(ParticlesCsv, RejectsNonPositiveRadiusAndNonFiniteValues) {
  const auto found = issues("x,y,z,r,vx\n1,2,3,0,0\n1,2,3,-1,0\n1,2,3,1,nan\n1,2,3,1,0\n");
  ASSERT_EQ(found.size(), 3U);
  EXPECT_THAT(found[0], AllOf(HasSubstr(":2: r: got 0"), HasSubstr("> 0")));
  EXPECT_THAT(found[1], HasSubstr(":3: r: got -1"));
  EXPECT_THAT(found[2], AllOf(HasSubstr(":4: vx: got nan"), HasSubstr("finite")));
}

// Where doubles are spaced more than a contact's geometry allows (z = 1e17: 16 R apart), or a
// position would wrap into the cell as 0 (x = 1e300), the file is refused by name.
TEST_F(ParticlesCsv, RejectsCoordinatesBeyondWhatDoublesResolve) {
  const auto found = issues("x,y,z,r\n1,2,1e17,1\n1e300,2,3,1\n1,2,3,1\n-999999,2,3,1\n");
  ASSERT_EQ(found.size(), 2U);
  EXPECT_THAT(found[0], AllOf(HasSubstr(":2: z: got 1e17"), HasSubstr("within ±1e+06 R")));
  EXPECT_THAT(found[1], HasSubstr(":3: x: got 1e300"));
}

TEST_F(ParticlesCsv, RejectsWrongFieldCount) {
  const auto found = issues("x,y,z,r\n1,2,3\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr(":2: got 3 fields, expected 4"));
}

TEST_F(ParticlesCsv, RejectsBadFixedFlag) {
  const auto found = issues("x,y,z,r,fixed\n1,2,3,1,2\n");
  ASSERT_EQ(found.size(), 1U);
  EXPECT_THAT(found[0], HasSubstr(":2: fixed: cannot read '2' as 0, 1, true or false"));
}

// pandas writes a bool column as True/False (DataFrame.to_csv)
TEST_F(ParticlesCsv, ReadsTheFixedFlagAsPandasWritesIt) {
  const fs::path file = write(",x,y,z,r,fixed\n0,1,2,3,1,False\n1,5,2,3,1,True\n");
  Bodies bodies;
  EXPECT_THROW(read_particles_csv(file, 1.0, bodies), ConfigError);  // the index column
  const fs::path plain = write("x,y,z,r,fixed\n1,2,3,1,False\n5,2,3,1,True\n");
  read_particles_csv(plain, 1.0, bodies);
  ASSERT_EQ(bodies.size(), 2U);
  EXPECT_EQ(bodies.fixed[0], 0);
  EXPECT_EQ(bodies.fixed[1], 1);
}

TEST_F(ParticlesCsv, RejectsAFileWithoutParticles) {
  EXPECT_THAT(issues("x,y,z,r\n# nothing\n"), ::testing::ElementsAre(HasSubstr("no particles")));
  EXPECT_THAT(issues(""), ::testing::ElementsAre(HasSubstr("no header")));
}

TEST_F(ParticlesCsv, ReportsAMissingFile) {
  Bodies bodies;
  EXPECT_THROW(read_particles_csv(dir_ / "absent.csv", 1.0, bodies), ConfigError);
}

/// A scene whose spheres need L ≥ 2 (2·1 + 0.01 + 0.05) = 4.12.
Scene small_scene(double lx, double ly) {
  Scene scene;
  scene.system.lx = lx;
  scene.system.ly = ly;
  scene.source = "scene.toml";
  return scene;
}

TEST(CheckBoxFits, AcceptsACellWideEnough) {
  Bodies bodies;
  bodies.add_sphere(Vec3(0.0, 0.0, 0.5), 1.0, 1.0);  // z < r: an overlap, not an error
  EXPECT_NO_THROW(check_box_fits(small_scene(4.13, 4.13), bodies));
}

TEST(CheckBoxFits, NamesTheSideThatIsTooShort) {
  Bodies bodies;
  bodies.add_sphere(Vec3(0.0, 0.0, 2.0), 1.0, 1.0);
  Scene scene = small_scene(25.0, 4.1);
  scene.step.laws.walls.cohesion_range = 0.02;  // the larger range counts: L ≥ 4.14
  try {
    check_box_fits(scene, bodies);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1U);
    const std::string text = format(error.issues()[0]);
    EXPECT_THAT(text, AllOf(HasSubstr("scene.toml: system.ly: got 4.1"), HasSubstr("= 4.14"),
                            HasSubstr("solver.skin"), HasSubstr("contact.cohesion_range")));
    // a deposit has no particles file: it once read "with R_max = 1 from ''"
    EXPECT_THAT(text, HasSubstr("with R_max = 1 of the deposit"));
  }
}

}  // namespace
}  // namespace cdpowder
