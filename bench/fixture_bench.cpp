// Whole steps from saved engine states (bench/fixtures/): every variant of the engine solves
// the same steps of the same packing, so the four factors of a run's time can be compared
// one by one: passes per step, ns per contact update (the NLGS stage, mixing included, over
// passes × contacts), and the per-step overhead (a step's time outside the NLGS stage:
// detection, building the local problems, warm start, integration, diagnostics).
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/step.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

namespace cdpowder::bench {
namespace {

/// The fixtures of bench/fixtures/README.md, in the order of the benchmark's argument.
constexpr std::array<const char*, 2> kFixtures = {"paper_front_mu00_t350.cdps",
                                                  "paper_mid_mu11_t240.cdps"};

constexpr int kStepsPerIteration = 100;

/// A saved engine state and the scene it resolves to.
struct Fixture {
  SavedRun saved;
  Scene scene;
};

/// The fixture of the benchmark's argument; nothing (and the benchmark skipped with the reason)
/// where its file is missing.
std::optional<Fixture> load_fixture(benchmark::State& state) {
  const std::filesystem::path file = std::filesystem::path(CDPOWDER_FIXTURE_DIR) /
                                     kFixtures.at(static_cast<std::size_t>(state.range(0)));
  if (!std::filesystem::exists(file)) {
    state.SkipWithError(
        ("missing " + file.string() + ": run bench/fixtures/make_fixtures.sh").c_str());
    return std::nullopt;
  }
  SavedRun saved = load_state(file);
  Scene scene = read_scene_text(saved.scene_toml, file.string(), {}, file.parent_path());
  return Fixture{std::move(saved), std::move(scene)};
}

void BM_FixtureSteps(benchmark::State& state) {
  const std::optional<Fixture> fixture = load_fixture(state);
  if (!fixture) return;
  const SavedRun& saved = fixture->saved;
  const Scene& scene = fixture->scene;
  std::int64_t steps = 0;
  std::int64_t passes = 0;
  double updates = 0.0;
  double nlgs_seconds = 0.0;
  double other_seconds = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    World world;
    StepWorkspace work(scene.step.solver.seed);
    RunState run;
    restore_run(saved, scene.run, scene.step.solver.dt, world, work, run);
    state.ResumeTiming();
    for (int k = 0; k < kStepsPerIteration; ++k) {
      const StepReport report = step(world, work, scene.step);
      ++steps;
      passes += report.solver.passes;
      updates += static_cast<double>(report.solver.passes) *
                 static_cast<double>(report.diagnostics.contacts);
      for (std::size_t s = 0; s < report.times.size(); ++s) {
        (s == static_cast<std::size_t>(Stage::SolveNlgs) ? nlgs_seconds : other_seconds) +=
            report.times[s];
      }
    }
  }
  state.counters["passes_per_step"] = static_cast<double>(sweeps) / static_cast<double>(steps);
  state.counters["ns_per_update"] = 1e9 * nlgs_seconds / updates;
  state.counters["overhead_us_per_step"] = 1e6 * other_seconds / static_cast<double>(steps);
  state.SetLabel(kFixtures.at(static_cast<std::size_t>(state.range(0))));
}

BENCHMARK(BM_FixtureSteps)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

/// Stage 2 alone (build_local_problems: the contacts' constants, cohesion, warm start and the
/// predicted velocities) on the contacts of a fixture's next step, after one whole step has
/// filled the warm-start cache: what one step of a run pays for it. Each call writes the same
/// records and velocities from the same inputs.
void BM_BuildLocalProblems(benchmark::State& state) {
  const std::optional<Fixture> fixture = load_fixture(state);
  if (!fixture) return;
  const SavedRun& saved = fixture->saved;
  const Scene& scene = fixture->scene;
  World world;
  StepWorkspace work(scene.step.solver.seed);
  RunState run;
  restore_run(saved, scene.run, scene.step.solver.dt, world, work, run);
  step(world, work, scene.step);
  begin_step(world, work, scene.step);
  for (auto _ : state) {
    build_local_problems(world, scene.step, work.action_cache, work.contacts, work.velocities);
    benchmark::DoNotOptimize(work.velocities.spheres.data());
  }
  state.counters["contacts"] = static_cast<double>(work.contacts.size());
  state.counters["ns_per_contact"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(work.contacts.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetLabel(kFixtures.at(static_cast<std::size_t>(state.range(0))));
}

BENCHMARK(BM_BuildLocalProblems)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace cdpowder::bench
