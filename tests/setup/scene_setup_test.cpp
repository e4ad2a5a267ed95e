// scene_setup_test.cpp — the World a scene describes: from the scene's own spheres, and around
// spheres a program made (make_world(scene, spheres) with SceneReadOptions::spheres_from_caller).
#include "cdpowder/setup/scene_setup.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

namespace cdpowder {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const std::filesystem::path kQuick =
    std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml";

Scene scene_for_callers_spheres(const std::vector<SceneOverride>& overrides = {}) {
  SceneReadOptions how;
  how.spheres_from_caller = true;
  return read_scene(kQuick, overrides, how);
}

TEST(SceneSetup, SpheresFromTheCallerDropTheScenesDepositFromTheResolvedScene) {
  const Scene scene = scene_for_callers_spheres();
  EXPECT_FALSE(scene.deposition.has_value());
  EXPECT_TRUE(scene.particles_file.empty());
  EXPECT_THAT(scene.effective_toml, Not(HasSubstr("[deposition]")));
  EXPECT_THAT(scene.effective_toml, Not(HasSubstr("[particles]")));
  // the rest of the scene as read without the option
  EXPECT_EQ(scene.system.lx, read_scene(kQuick, {}).system.lx);
}

TEST(SceneSetup, TheScenesDepositAsTheCallersSpheresGivesTheSameWorld) {
  const Scene with_deposit = read_scene(kQuick, {});
  const World deposit = make_world(with_deposit);
  const World copy = make_world(scene_for_callers_spheres(), deposit.bodies);
  EXPECT_EQ(copy.bodies.position, deposit.bodies.position);
  EXPECT_EQ(copy.bodies.inverse_mass, deposit.bodies.inverse_mass);
  EXPECT_EQ(copy.box.lx, deposit.box.lx);
  EXPECT_EQ(copy.walls.bottom.enabled, deposit.walls.bottom.enabled);
  EXPECT_EQ(copy.walls.piston.height, deposit.walls.piston.height);
  EXPECT_EQ(copy.walls.piston.force, deposit.walls.piston.force);
  EXPECT_EQ(copy.walls.piston.mass, deposit.walls.piston.mass);
}

TEST(SceneSetup, ThePistonRestsOnTheHighestOfTheCallersSpheresPlusTheGap) {
  Bodies spheres;
  spheres.add_sphere(Vec3(1.0, 1.0, 1.0), 1.0, 1.0);
  spheres.add_sphere(Vec3(5.0, 5.0, 3.5), 0.5, 1.0);
  const World world = make_world(scene_for_callers_spheres({"piston.start_gap=0.25"}), spheres);
  EXPECT_DOUBLE_EQ(world.walls.piston.height, 3.5 + 0.5 + 0.25);
  EXPECT_EQ(world.bodies.size(), 2U);
}

TEST(SceneSetup, ACellTooSmallForTheCallersSpheresIsNamed) {
  Bodies spheres;
  spheres.add_sphere(Vec3(1.0, 1.0, 8.0), 8.0, 1.0);  // 2 (2·8 + d + skin) > 15
  try {
    (void)make_world(scene_for_callers_spheres(), spheres);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("system.lx"));
  }
}

}  // namespace
}  // namespace cdpowder
