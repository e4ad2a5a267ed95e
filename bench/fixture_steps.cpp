// fixture_steps — continues a saved state (bench/fixtures/) for N steps with scene overrides
// and prints what the speed work compares: passes per step, capped steps, ns per contact
// update in the NLGS stage, the per-step overhead outside it, wall time, and the final
// porosity and state hash. Same state, same steps: the variants differ only by the override.
// With --run-loop the steps go through run_simulation (run/run_loop.hpp), so the
// overhead includes what the loop adds to a step (the undo copy of an adaptive Δt, the
// blocked-state test); step() alone does not see it.
// --always-threaded keeps every cut step on the threads with solver.threads = 2, so that a
// measurement of the threads is not mixed with the blocks the timed choice runs on one thread.
// With solver.threads ≥ 2 it also prints the round trip of a cache line between CPUs 0 and 1
// just before and just after the steps: on a virtual machine that path changes while the
// steps run, and a two-thread time is read beside it (docs/performance.md, "Two threads";
// docs/lab/2026-11-27-two-threads-and-the-core-path.md).
//   fixture_steps FILE.cdps --steps N [--run-loop] [--always-threaded] [--set section.key=value
//   ...]
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/run/state_hash.hpp"
#include "cdpowder/solver/step.hpp"
#include "support/core_round_trip.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

namespace {

/// What the printout sums over the steps.
struct Totals {
  std::int64_t steps = 0;
  std::int64_t passes = 0;
  std::int64_t capped = 0;
  std::int64_t repeated = 0;  ///< adaptive steps undone and solved again (--run-loop)
  std::int64_t threaded = 0;  ///< steps solved on more than one thread (solver.threads)
  double opening = 0.0;       ///< largest opening per step [d_coh]
  double updates = 0.0;       ///< contact updates of the NLGS stage
  double wall = 0.0;          ///< [s]
  cdpowder::StageTimes stages{};
};

void add_step(const cdpowder::StepReport& report, Totals& totals) {
  ++totals.steps;
  totals.passes += report.solver.passes;
  totals.capped += report.solver.converged ? 0 : 1;
  totals.threaded += report.solver.threaded ? 1 : 0;
  totals.opening = std::max(totals.opening, report.diagnostics.max_cohesive_opening_per_range);
  totals.updates +=
      static_cast<double>(report.solver.passes) * static_cast<double>(report.diagnostics.contacts);
}

/// N calls of step().
Totals run_steps(cdpowder::World& world, cdpowder::StepWorkspace& work,
                 const cdpowder::Scene& scene, int steps) {
  Totals totals;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) {
    const cdpowder::StepReport report = step(world, work, scene.step);
    add_step(report, totals);
    for (std::size_t s = 0; s < report.times.size(); ++s) totals.stages[s] += report.times[s];
  }
  totals.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return totals;
}

/// N steps of run_simulation with the scene's run settings (a fresh run from the saved state,
/// stopped after N steps); undone adaptive steps count in the stage times, not in the steps.
Totals run_loop_steps(cdpowder::World& world, cdpowder::StepWorkspace& work,
                      const cdpowder::Scene& scene, int steps) {
  Totals totals;
  cdpowder::RunConfig run = scene.run;
  run.duration = run.max_duration = 1e9;  // [t0]: the step count stops the run
  const auto observer = [&](const cdpowder::World&, const cdpowder::StepReport& report, double) {
    add_step(report, totals);
  };
  const auto enough = [&] { return totals.steps >= steps; };
  const cdpowder::RunResult result = run_simulation(world, work, scene.step, run, observer, enough);
  totals.repeated = result.repeated_steps;
  totals.stages = result.stage_seconds;
  totals.wall = result.wall_seconds;
  return totals;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cdpowder;
  CLI::App cli{"Continues a saved engine state for N steps and prints the step costs."};
  std::filesystem::path file;
  int steps = 100;
  bool run_loop = false;
  std::vector<std::string> overrides;
  cli.add_option("state", file, "state file (.cdps)")->required()->check(CLI::ExistingFile);
  cli.add_option("--steps", steps, "steps to run")->check(CLI::PositiveNumber);
  cli.add_flag("--run-loop", run_loop, "step through run_simulation (adaptive dt, undo copies)");
  bool always_threaded = false;
  cli.add_flag("--always-threaded", always_threaded,
               "with solver.threads = 2, every cut step on the threads (no timed choice)");
  cli.add_option("--set", overrides, "section.key=value override of the saved scene");
  CLI11_PARSE(cli, argc, argv);
  try {
    SavedRun saved = load_state(file);
    // the state is restored with the scene it was saved with; the steps use the overrides
    const Scene saved_scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
    const Scene scene =
        read_scene_text(saved.scene_toml, file.string(), command_line_overrides(overrides), ".");
    World world;
    StepWorkspace work(scene.step.solver.seed);
    if (always_threaded) work.solver.thread_choice.always_threaded();
    RunState restored;
    restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work,
                restored);
    const bool threads = scene.step.solver.threads >= 2;
    const double round_trip_before = threads ? bench::core_round_trip_ns() : 0.0;
    const Totals t =
        run_loop ? run_loop_steps(world, work, scene, steps) : run_steps(world, work, scene, steps);
    const double round_trip_after = threads ? bench::core_round_trip_ns() : 0.0;
    const auto solve = static_cast<std::size_t>(Stage::SolveNlgs);
    // the overhead is everything but the NLGS stage: in --run-loop mode the wall time of the
    // loop (its undo copies included) minus the NLGS stage
    const double stage_sum = std::accumulate(t.stages.begin(), t.stages.end(), 0.0);
    const double other = (run_loop ? t.wall : stage_sum) - t.stages[solve];
    const auto n = static_cast<double>(t.steps);
    fmt::print(
        "steps={} passes/step={:.1f} capped={} repeated={} threaded={} ns/update={:.1f} "
        "overhead={:.0f}us/step opening/step={:.3f}d_coh wall={:.2f}s porosity={:.6f} "
        "hash={}\n",
        t.steps, static_cast<double>(t.passes) / n, t.capped, t.repeated, t.threaded,
        1e9 * t.stages[solve] / t.updates, 1e6 * other / n, t.opening, t.wall, porosity(world),
        hash_text(state_hash(world, work)));
    // the last step's colouring: what the threads of solver.threads share, and what they do not
    const ColouredPass& coloured = work.solver.coloured;
    if (scene.step.solver.kernel == PassKernel::Coloured) {
      fmt::print(
          "last step: contacts={} (of {} listed pairs) colours={} batches={} sequential={} "
          "(walls {})\n",
          work.contacts.size(), work.candidates.pairs().size(), coloured.colours(),
          coloured.batches(), coloured.sequential.size(), work.contacts.walls.size());
      // the parts of a tiled step (tiles.hpp): batched pairs + sequential contacts, phase by
      // phase, then the hub
      const PairColouring& colouring = coloured.colouring;
      std::string parts;
      for (std::size_t p = 0; p < coloured.parts(); ++p) {
        const bool new_phase = std::find(coloured.phase_parts.begin(), coloured.phase_parts.end(),
                                         p) != coloured.phase_parts.end();
        parts += fmt::format("{}{}+{}", new_phase ? " |" : " ",
                             colouring.first_member(p + 1) - colouring.first_member(p),
                             coloured.part_sequential[p + 1] - coloured.part_sequential[p]);
      }
      const TileGrid grid = work.solver.tiles.grid;
      fmt::print("last step: {} × {} tiles; parts (| a phase, the hub last){}\n", grid.nx, grid.ny,
                 parts);
    }
    fmt::print(
        "per step [us]: detect {:.0f}, build {:.0f}, solve {:.0f}, integrate {:.0f}, "
        "analyse {:.0f}, outside the stages {:.0f}\n",
        1e6 * t.stages[0] / n, 1e6 * t.stages[1] / n, 1e6 * t.stages[2] / n, 1e6 * t.stages[3] / n,
        1e6 * t.stages[4] / n, run_loop ? 1e6 * (t.wall - stage_sum) / n : 0.0);
    if (threads) {
      fmt::print("core round trip [ns], CPU 0 to 1 and back: {:.0f} before, {:.0f} after\n",
                 round_trip_before, round_trip_after);
    }
    return 0;
  } catch (const std::exception& error) {
    fmt::print(stderr, "fixture_steps: {}\n", error.what());
    return 2;
  }
}
