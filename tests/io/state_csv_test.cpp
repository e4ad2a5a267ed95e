// Tests for src/cdpowder/io/state_csv.cpp: particles.csv reads back through the scene's particle
// reader bit for bit, and contacts.csv names the walls and the contact state as documented.
#include "cdpowder/io/state_csv.hpp"

#include "cdpowder/config/particles_csv.hpp"
#include "cdpowder/core/index.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {
namespace {

using ::testing::ElementsAre;
using ::testing::StartsWith;
namespace fs = std::filesystem;

constexpr double kDensity = 1.0;  // ρ; the CSV holds no masses, so any value will do

/// The bits of a double: equal bits, not merely ==, so −0 ≠ +0 and no last-digit loss hides.
std::uint64_t bits(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

/// Expects every component of `a` and `b` to have the same bits.
void expect_same_bits(const Vec3& a, const Vec3& b, const std::string& what) {
  for (Eigen::Index k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(a[k]), bits(b[k])) << what << "[" << k << "]: " << a[k] << " vs " << b[k];
  }
}

/// Two spheres whose numbers need all 17 significant digits (or a sign bit) to read back.
Bodies two_spheres() {
  Bodies bodies;
  bodies.add_sphere(Vec3(0.1 + 0.2, 1.0 / 3.0, 2.0 / 7.0), 1.0 + 0x1p-52, kDensity);
  bodies.add_sphere(Vec3(-12.345678901234567, 1e-300, 24.999999999999996), 0.7, kDensity,
                    /*is_fixed=*/true);
  bodies.velocity[0] = Vec3(-0.0, 1.0 / 7.0, -3e-17);
  bodies.velocity[1] = Vec3(1e300, -2.0 / 3.0, 0.1);
  bodies.angular_velocity[0] = Vec3(5.0 / 9.0, -0.0, 123456.789);
  bodies.angular_velocity[1] = Vec3(-1.0 / 11.0, 4e-9, 0.0);
  bodies.external_force[0] = Vec3(0.0, 0.0, -1.0 / 400.0);
  bodies.external_force[1] = Vec3(3.14159265358979, -2.718281828459045, 1.0 / 13.0);
  bodies.external_torque[0] = Vec3(1.0 / 17.0, -1.0 / 19.0, 1.0 / 23.0);
  bodies.external_torque[1] = Vec3(-0.0, 7e-7, -1.0 / 29.0);
  return bodies;
}

TEST(ParticlesCsvWriter, ReadsBackThroughTheParticleReaderBitForBit) {
  const fs::path file = fs::temp_directory_path() /
                        ("cdpowder_state_csv_" + std::to_string(std::random_device{}()) + ".csv");
  const Bodies written = two_spheres();
  std::ofstream(file) << particles_csv(written, "# cdpowder test\n# seed = 1\n");
  Bodies read;
  read_particles_csv(file, kDensity, read);
  fs::remove(file);

  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    const std::string sphere = "sphere " + std::to_string(i) + " ";
    expect_same_bits(read.position[i], written.position[i], sphere + "position");
    EXPECT_EQ(bits(read.radius[i]), bits(written.radius[i])) << sphere << "radius";
    expect_same_bits(read.velocity[i], written.velocity[i], sphere + "velocity");
    expect_same_bits(read.angular_velocity[i], written.angular_velocity[i],
                     sphere + "angular velocity");
    expect_same_bits(read.external_force[i], written.external_force[i], sphere + "force");
    expect_same_bits(read.external_torque[i], written.external_torque[i], sphere + "torque");
    EXPECT_EQ(read.fixed[i], written.fixed[i]) << sphere << "fixed";
  }
  EXPECT_THAT(read.fixed, ElementsAre(0, 1));
}

/// The data rows of a CSV text: no '#' lines and no column-name line.
std::vector<std::string> data_rows(const std::string& text) {
  std::vector<std::string> rows;
  std::istringstream lines(text);
  std::string line;
  bool header_seen = false;
  while (std::getline(lines, line)) {
    if (line.starts_with('#')) {
      continue;
    }
    if (header_seen) {
      rows.push_back(line);
    }
    header_seen = true;
  }
  return rows;
}

/// The fields of one CSV row.
std::vector<std::string> fields(const std::string& row) {
  std::vector<std::string> result;
  std::istringstream stream(row);
  for (std::string field; std::getline(stream, field, ',');) {
    result.push_back(field);
  }
  return result;
}

// Columns a, b, nx, ny, nz, normal_force, tx, ty, tz, rx, ry, rz, twist, gap, cohesive, state.
constexpr std::size_t kStateColumn = 15;

/// One sphere pair and one contact with each wall; S = R_n + F_c decides closed or open.
Contacts three_contacts() {
  Contacts contacts;
  PairProblem pair;
  pair.a = 0;
  pair.b = 1;
  pair.normal = Vec3::UnitX();
  pair.cohesion = 1.0;
  contacts.pairs.push_back(pair);
  ContactAction pulled;
  pulled.normal_force = -0.5;  // S = −0.5 + 1 > 0: a cohesive bond under tension is closed
  contacts.pair_actions.push_back(pulled);
  contacts.pair_cohesive.push_back(1);

  WallProblem bottom;
  bottom.sphere = 1;
  bottom.wall = WallKind::Bottom;
  bottom.normal = Vec3::UnitZ();
  bottom.cohesion = 1.0;
  contacts.walls.push_back(bottom);
  ContactAction torn;
  torn.normal_force = -1.0;  // S = −1 + 1 = 0: not > 0, so open
  contacts.wall_actions.push_back(torn);
  contacts.wall_cohesive.push_back(1);

  WallProblem piston;
  piston.sphere = 0;
  piston.wall = WallKind::Piston;
  piston.normal = -Vec3::UnitZ();
  piston.cohesion = 0.0;
  contacts.walls.push_back(piston);
  ContactAction pushed;
  pushed.normal_force = 0.25;  // S = 0.25 > 0 without cohesion: closed
  contacts.wall_actions.push_back(pushed);
  contacts.wall_cohesive.push_back(0);
  return contacts;
}

/// A sink that keeps every chunk it is handed.
class Chunks final : public OutputSink {
 public:
  void write(std::string_view bytes) override { chunks.emplace_back(bytes); }

  std::vector<std::string> chunks;
};

// The writer hands its file over in chunks of about kOutputChunkBytes, never the whole file:
// 20 000 spheres, ≈ 4 MB of text, in chunks of at most a chunk and one row.
TEST(ParticlesCsvWriter, HandsTheFileOverInChunks) {
  Bodies bodies;
  for (int i = 0; i < 20000; ++i) {
    bodies.add_sphere(Vec3(0.1 * i, 1.0 / (i + 1), 2.0), 1.0, kDensity);
  }
  Chunks sink;
  write_particles_csv(sink, bodies, "# header\n");
  ASSERT_GT(sink.chunks.size(), 10U);
  std::string whole;
  for (const std::string& chunk : sink.chunks) {
    EXPECT_LT(chunk.size(), kOutputChunkBytes + 512);
    whole += chunk;
  }
  EXPECT_EQ(whole, particles_csv(bodies, "# header\n"));
}

TEST(ContactsCsv, NamesBottomWallMinusOneAndPistonMinusTwoInColumnA) {
  const std::vector<std::string> rows = data_rows(contacts_csv(three_contacts(), "# test\n"));
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_THAT(rows[0], StartsWith("0,1,"));
  EXPECT_THAT(rows[1], StartsWith("-1,1,"));
  EXPECT_THAT(rows[2], StartsWith("-2,0,"));
  EXPECT_EQ(kBottomWallId, -1);
  EXPECT_EQ(kPistonId, -2);
}

TEST(ContactsCsv, WritesClosedOnlyWhenNormalForcePlusCohesionIsPositive) {
  const std::string text = contacts_csv(three_contacts(), "");
  std::istringstream lines(text);
  std::string header;
  std::getline(lines, header);
  ASSERT_EQ(fields(header).size(), kStateColumn + 1);
  EXPECT_EQ(fields(header)[kStateColumn], "state");
  std::vector<std::string> states;
  for (const std::string& row : data_rows(text)) {
    ASSERT_EQ(fields(row).size(), kStateColumn + 1) << row;
    states.push_back(fields(row)[kStateColumn]);
  }
  EXPECT_THAT(states, ElementsAre("closed", "open", "closed"));
}

}  // namespace
}  // namespace cdpowder
