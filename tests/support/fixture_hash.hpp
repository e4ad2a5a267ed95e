// fixture_hash.hpp — the state hash after a few steps from one of the bench's saved paper-size
// states (bench/fixtures/*.cdps, ≈ 1 000 spheres: cut into two slabs, slabs.hpp), shared by the
// regression net and the tests of the two threads.
#pragma once

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/run/state_hash.hpp"
#include "cdpowder/solver/step.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace cdpowder::testing {

/// The hash after `steps` steps (step(), a fixed Δt) of bench/fixtures/`name`, its saved scene
/// with `overrides` (TOML key=value, as --set); with `release_after` ≥ 0, the step scratch is
/// freed (release_step_scratch) after that many steps.
inline std::uint64_t fixture_hash(const std::string& name, int steps,
                                  const std::vector<SceneOverride>& overrides,
                                  int release_after = -1) {
  const std::filesystem::path file =
      std::filesystem::path(CDPOWDER_SOURCE_DIR) / "bench/fixtures" / name;
  SavedRun saved = load_state(file);
  const Scene saved_scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
  const Scene scene = read_scene_text(saved.scene_toml, file.string(), overrides, ".");
  World world;
  StepWorkspace work(scene.step.solver.seed);
  RunState run;
  restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work, run);
  for (int k = 0; k < steps; ++k) {
    if (k == release_after) release_step_scratch(work);
    step(world, work, scene.step);
  }
  return state_hash(world, work);
}

}  // namespace cdpowder::testing
