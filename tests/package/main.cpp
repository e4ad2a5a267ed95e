// A user's program on the installed library: the quick example compacted for a short time,
// from the one public header. Prints the porosity and the run's result line.
//   package_user SCENE.toml
#include <cdpowder/cdpowder.hpp>
#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: package_user SCENE.toml\n");
    return 2;
  }
  try {
    cdpowder::SceneReadOptions options;
    options.compaction = true;
    const cdpowder::Scene scene =
        cdpowder::read_scene(argv[1], {"run.max_duration=5", "contact.mu_roll=0.3"}, options);
    cdpowder::World world = cdpowder::make_world(scene);
    const double before = cdpowder::porosity(world);
    cdpowder::StepWorkspace work(scene.step.solver.seed);
    int steps = 0;
    const cdpowder::RunResult result = cdpowder::run_simulation(
        world, work, scene.step, scene.run,
        [&](const cdpowder::World&, const cdpowder::StepReport&, double) { ++steps; });
    std::printf("cdpowder %s: porosity %.5f -> %.5f after %d steps\n%s\n", cdpowder::kVersion,
                before, cdpowder::porosity(world), steps,
                cdpowder::result_line(scene, world, work.contacts, result).c_str());
    return steps > 0 && cdpowder::porosity(world) < before ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
