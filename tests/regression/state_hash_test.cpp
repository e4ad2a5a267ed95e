// The regression net: state hashes (run/state_hash.hpp) of short scenes against golden
// values in tests/regression/golden_hashes.txt. Any change that moves a result by one ulp
// fails here. If the change is intended, update the golden value in the same commit and say
// why in its message; the test prints the new value, and
//   CDPOWDER_UPDATE_GOLDEN=1 ctest --preset release -R StateHash
// rewrites the file. A build whose arithmetic differs from the others (none so far: the
// release and the sanitizer builds agree bit for bit) gets lines of its own (docs/testing.md).
#include "cdpowder/run/state_hash.hpp"

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "support/fixture_hash.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace cdpowder::testing {
namespace {

const std::filesystem::path kGoldenFile =
    std::filesystem::path(CDPOWDER_SOURCE_DIR) / "tests/regression/golden_hashes.txt";

/// "release", "debug+sanitize", …: golden lines for this build, else those marked "any".
constexpr const char* kBuildKind = CDPOWDER_BUILD_KIND;

struct GoldenLine {
  std::string scene;
  std::string build;
  std::string hash;
};

std::vector<GoldenLine> read_golden() {
  std::vector<GoldenLine> lines;
  std::ifstream file(kGoldenFile);
  std::string text;
  while (std::getline(file, text)) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream fields(text);
    GoldenLine line;
    fields >> line.scene >> line.build >> line.hash;
    lines.push_back(line);
  }
  return lines;
}

/// Replaces (or adds) the golden value of `scene` for this build: its own line if it has
/// one, else the "any" line.
void update_golden(const std::string& scene, const std::string& hash) {
  std::ifstream in(kGoldenFile);
  std::vector<std::string> lines;
  std::string text;
  bool own_line = false;
  while (std::getline(in, text)) {
    lines.push_back(text);
    own_line = own_line || text.starts_with(scene + " " + kBuildKind + " ");
  }
  const std::string prefix = scene + " " + (own_line ? kBuildKind : "any") + " ";
  bool replaced = false;
  for (std::string& line : lines) {
    if (line.starts_with(prefix)) {
      line = prefix + hash;
      replaced = true;
    }
  }
  if (!replaced) lines.push_back(prefix + hash);
  std::ofstream out(kGoldenFile, std::ios::trunc);
  for (const std::string& line : lines) out << line << '\n';
}

void expect_golden(const std::string& scene, std::uint64_t hash) {
  const std::string now = hash_text(hash);
  std::string golden;
  for (const GoldenLine& line : read_golden()) {
    if (line.scene != scene) continue;
    if (line.build == kBuildKind || (line.build == "any" && golden.empty())) golden = line.hash;
  }
  if (golden == now) return;
  const char* update = std::getenv("CDPOWDER_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    update_golden(scene, now);
    return;
  }
  ADD_FAILURE() << fmt::format(
      "the state of '{}' changed ({} build): golden {}, now {}.\n"
      "If the change is intended, set the new value in {} in the same commit and give the "
      "reason in the commit message (CDPOWDER_UPDATE_GOLDEN=1 rewrites it); otherwise it is "
      "a bug.",
      scene, kBuildKind, golden.empty() ? "(none)" : golden, now, kGoldenFile.string());
}

Scene quick_scene(const std::vector<SceneOverride>& overrides) {
  SceneReadOptions options;
  options.compaction = true;
  return read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml",
                    overrides, options);
}

/// Hash after the first `duration` t0 of the scene's compaction.
std::uint64_t hash_after(const Scene& scene) {
  World world = make_world(scene);
  StepWorkspace work(scene.step.solver.seed);
  run_simulation(world, work, scene.step, scene.run, {});
  return state_hash(world, work);
}

// The quick example's ballistic deposit of 100 spheres (capture radius 3R).
TEST(StateHash, Deposit) {
  const Scene scene = quick_scene({});
  expect_golden("deposit_100",
                state_hash(make_world(scene), StepWorkspace(scene.step.solver.seed)));
}

// The first 300 steps of the quick compaction at (μt, μn) = (1, 1) and (0, 0).
TEST(StateHash, CompactionWithTorques) {
  expect_golden("compact_quick_mu11_300steps", hash_after(quick_scene({"run.max_duration=3"})));
}

TEST(StateHash, CompactionWithoutTorques) {
  expect_golden(
      "compact_quick_mu00_300steps",
      hash_after(quick_scene({"run.max_duration=3", "contact.mu_roll=0", "contact.mu_twist=0"})));
}

// The scalar kernel (solver.kernel = "scalar") on the first 300 steps at (1, 1) and (0, 0).
TEST(StateHash, CompactionWithTheScalarKernel) {
  expect_golden("compact_quick_mu11_300steps_scalar",
                hash_after(quick_scene({"run.max_duration=3", "solver.kernel=\"scalar\""})));
  expect_golden("compact_quick_mu00_300steps_scalar",
                hash_after(quick_scene({"run.max_duration=3", "contact.mu_roll=0",
                                        "contact.mu_twist=0", "solver.kernel=\"scalar\""})));
}

// The first 60 t0 of the (0, 0) compaction with the adaptive time step.
TEST(StateHash, AdaptiveCompaction) {
  expect_golden("compact_quick_mu00_adaptive_60t0",
                hash_after(quick_scene({"run.max_duration=60", "contact.mu_roll=0",
                                        "contact.mu_twist=0", "solver.adaptive_dt=true"})));
}

// Radii uniform in [0.7, 1.3] R (c ≠ 0 couples sliding and rolling, §5.2), μt = μn = 0.3,
// otherwise the quick example.
constexpr const char* kPolydisperseScene = R"(
[system]
lx = 15.0
ly = 15.0
[deposition]
spheres = 100
radius_min = 0.7
radius_max = 1.3
capture_radius = 3.0
seed = 3
[contact]
mu = 0.3
mu_roll = 0.3
mu_twist = 0.3
[piston]
enabled = true
mass = 360.0
pressure = 0.0025
[solver]
tolerance = 1e-3
max_passes = 200
[run]
until_blocked = true
max_duration = 3.0
)";

TEST(StateHash, PolydisperseCompaction) {
  SceneReadOptions options;
  options.compaction = true;
  const Scene scene = read_scene_text(kPolydisperseScene, "polydisperse", {}, ".", options);
  expect_golden("compact_polydisperse_mu03_300steps", hash_after(scene));
}

// Ten steps of the paper-size fixtures (≈ 1 000 spheres, so each step is cut into two slabs,
// slabs.hpp) with the kinematic rule on: the (0, 0) compaction front and the (1, 1) mid-run.
TEST(StateHash, PaperSizeSteps) {
  const std::vector<SceneOverride> settings{"solver.kinematic_tolerance=1e-4"};
  expect_golden("paper_front_mu00_10steps",
                fixture_hash("paper_front_mu00_t350.cdps", 10, settings));
  expect_golden("paper_mid_mu11_10steps", fixture_hash("paper_mid_mu11_t240.cdps", 10, settings));
}

}  // namespace
}  // namespace cdpowder::testing
