// make_fixture — runs a scene's compaction to a given time and saves the engine state there
// (run/state_file.hpp): the fixtures that the speed work measures each lever on, so that
// every variant solves exactly the same steps. bench/fixtures/README.md lists the fixtures
// and the commands that made them.
//   make_fixture SCENE.toml --time T --out FILE.cdps [--set section.key=value ...]
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/run/state_hash.hpp"
#include "cdpowder/setup/scene_setup.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>
#include <filesystem>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  CLI::App cli{"Runs a scene's compaction to time T and saves the engine state there."};
  std::filesystem::path scene_file;
  std::filesystem::path out;
  double time = 0.0;
  std::vector<std::string> overrides;
  cli.add_option("scene", scene_file, "scene TOML")->required()->check(CLI::ExistingFile);
  cli.add_option("--time", time, "simulated time of the saved state [t0]")->required();
  cli.add_option("--out", out, "state file to write")->required();
  cli.add_option("--set", overrides, "section.key=value override (repeatable)");
  CLI11_PARSE(cli, argc, argv);
  try {
    cdpowder::SceneReadOptions options;
    options.compaction = true;
    const cdpowder::Scene scene =
        cdpowder::read_scene(scene_file, cdpowder::command_line_overrides(overrides), options);
    cdpowder::World world = cdpowder::make_world(scene);
    cdpowder::StepWorkspace work(scene.step.solver.seed);
    cdpowder::RunState state;
    const cdpowder::RunResult& result =
        cdpowder::run_simulation(world, work, scene.step, scene.run, state, {},
                                 [&] { return world.time >= time - 0.5 * scene.step.solver.dt; });
    if (!result.interrupted) {
      fmt::print(stderr, "make_fixture: the run ended (blocked={}) at t = {} before t = {}\n",
                 result.blocked, world.time, time);
      return 1;
    }
    cdpowder::save_state(out, scene.effective_toml, world, work, state);
    fmt::print("{}: t = {} t0, step {}, {} spheres, {} stored actions, state hash {}\n",
               out.string(), world.time, world.step, world.bodies.size(),
               cdpowder::last_step_actions(work).pairs.size() +
                   cdpowder::last_step_actions(work).walls.size(),
               cdpowder::hash_text(cdpowder::state_hash(world, work)));
    return 0;
  } catch (const std::exception& error) {
    fmt::print(stderr, "make_fixture: {}\n", error.what());
    return 2;
  }
}
