// fixture_steps — continues a saved state (bench/fixtures/) for N steps with scene overrides
// and prints what the speed work compares: sweeps per step, capped steps, ns per contact
// update in the NLGS stage, the per-step overhead outside it, wall time, and the final
// porosity and state hash. Same state, same steps: the variants differ only by the override.
//   fixture_steps FILE.cdps --steps N [--set section.key=value ...]
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/io/state_file.hpp"
#include "cdpowder/io/state_hash.hpp"
#include "cdpowder/solver/step.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace cdpowder;
  CLI::App cli{"Continues a saved engine state for N steps and prints the step costs."};
  std::filesystem::path file;
  int steps = 100;
  std::vector<std::string> overrides;
  cli.add_option("state", file, "state file (.cdps)")->required()->check(CLI::ExistingFile);
  cli.add_option("--steps", steps, "steps to run")->check(CLI::PositiveNumber);
  cli.add_option("--set", overrides, "section.key=value override of the saved scene");
  CLI11_PARSE(cli, argc, argv);
  try {
    SavedRun saved = load_state(file);
    // the state is restored with the scene it was saved with; the steps use the overrides
    const Scene saved_scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
    const Scene scene = read_scene_text(saved.scene_toml, file.string(), overrides, ".");
    World world;
    StepWorkspace work(scene.step.solver.seed);
    RunState run;
    restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work, run);
    std::int64_t sweeps = 0;
    int capped = 0;
    double opening = 0.0;
    double updates = 0.0;
    double nlgs = 0.0;
    double other = 0.0;
    StageTimes stages{};
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k) {
      const StepReport report = step(world, work, scene.step);
      sweeps += report.solver.sweeps;
      capped += report.solver.converged ? 0 : 1;
      opening = std::max(opening, report.diagnostics.max_cohesive_opening_per_range);
      updates += static_cast<double>(report.solver.sweeps) *
                 static_cast<double>(report.diagnostics.contacts);
      for (std::size_t s = 0; s < report.times.size(); ++s) {
        (s == static_cast<std::size_t>(Stage::SolveNlgs) ? nlgs : other) += report.times[s];
        stages[s] += report.times[s];
      }
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(
        "steps={} sweeps/step={:.1f} capped={} ns/update={:.1f} overhead={:.0f}us/step "
        "opening/step={:.3f}d_coh wall={:.2f}s porosity={:.6f} hash={}\n",
        steps, static_cast<double>(sweeps) / steps, capped, 1e9 * nlgs / updates,
        1e6 * other / steps, opening, wall, porosity(world),
        hash_text(state_hash(world, work.action_cache)));
    fmt::print(
        "per step [us]: detect {:.0f}, build {:.0f}, solve {:.0f}, integrate {:.0f}, "
        "analyse {:.0f}\n",
        1e6 * stages[0] / steps, 1e6 * stages[1] / steps, 1e6 * stages[2] / steps,
        1e6 * stages[3] / steps, 1e6 * stages[4] / steps);
    return 0;
  } catch (const std::exception& error) {
    fmt::print(stderr, "fixture_steps: {}\n", error.what());
    return 2;
  }
}
