// step.cpp — the time step as a table of contents. The stages run in this order only;
// each reads what the one before it wrote. Contact geometry is frozen after stage 1 (§3).
#include "cdpowder/solver/step.hpp"

#include "cdpowder/analysis/cohesive_opening.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/integrate.hpp"
#include "cdpowder/solver/slabs.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace cdpowder {

namespace {

class StageClock {
 public:
  void lap(Stage stage, StageTimes& times) {
    const auto now = std::chrono::steady_clock::now();
    times[static_cast<std::size_t>(stage)] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

StepReport step(World& world, StepWorkspace& work, const StepSettings& settings) {
  StepReport report = begin_step(world, work, settings);
  finish_step(world, work, settings, report);
  return report;
}

StepReport begin_step(World& world, StepWorkspace& work, const StepSettings& settings) {
  StepReport report;
  report.dt = settings.solver.dt;
  StageClock clock;
  // on the threads where the last step's solve was (a step too small to cut, or one the
  // ThreadChoice keeps on one thread, keeps these stages there too); parked after them, as a
  // caller of begin_step alone may never solve
  SlabThreads* const threads = work.threaded && settings.solver.threads >= 2
                                   ? work.solver.threads.get(std::min(settings.solver.threads, 2))
                                   : nullptr;

  detect_contacts(world, settings.detection(), work.grid, work.contacts, &work.candidates, threads,
                  &work.detection);
  clock.lap(Stage::DetectContacts, report.times);

  build_local_problems(world, settings, work.action_cache, work.contacts, work.velocities, threads);
  if (threads != nullptr) threads->park();
  clock.lap(Stage::BuildLocalProblems, report.times);
  return report;
}

void finish_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report) {
  solve_step(world, work, settings, report);
  commit_step(world, work, settings, report);
}

namespace {

/// The workers of a step whose solve ran on them (report.solver.threaded), for the stages
/// after it; nullptr otherwise. A step the ThreadChoice keeps on one thread (the second core
/// was slower lately) keeps its other stages there too.
SlabThreads* stage_threads(StepWorkspace& work, const StepSettings& settings,
                           const StepReport& report) {
  if (!report.solver.threaded || settings.solver.threads < 2) return nullptr;
  return work.solver.threads.get(std::min(settings.solver.threads, 2));
}

/// Runs first() and second() side by side on `threads` (one after the other on the caller
/// when null), then lets the workers rest: the two must write nothing in common.
template <typename First, typename Second>
void side_by_side(SlabThreads* threads, const First& first, const Second& second) {
  run_pieces(threads, 2, [&](std::uint32_t piece) {
    if (piece == 0) {
      first();
    } else {
      second();
    }
  });
  if (threads != nullptr) threads->park();
}

}  // namespace

void solve_step(const World& world, StepWorkspace& work, const StepSettings& settings,
                StepReport& report) {
  StageClock clock;
  const double reference_force = settings.laws.spheres.cohesion_force;
  NlgsWorkspace& solver = work.solver;
  cut_into_slabs(world.bodies.position, work.contacts, solver.slab, solver.slab_scratch);
  report.solver = solve_nlgs(work.contacts, work.velocities, settings.solver, reference_force,
                             solver, solver.slab);
  work.threaded = report.solver.threaded;
  clock.lap(Stage::SolveNlgs, report.times);

  // the opening gauge, and the net force while `world` still holds the old velocities: both
  // only read, so side by side on a threaded step
  CohesiveOpening opening;
  double net_force = 0.0;
  side_by_side(
      stage_threads(work, settings, report),
      [&] {
        opening = cohesive_opening(world, work.contacts, work.velocities, settings.laws,
                                   settings.solver.dt);
      },
      [&] { net_force = net_force_of_step(world.bodies, work.velocities); });
  report.diagnostics.max_cohesive_opening_speed = opening.speed;
  report.diagnostics.max_cohesive_opening_per_range = opening.per_range;
  report.diagnostics.max_net_force = net_force;
  clock.lap(Stage::Analyse, report.times);
}

void commit_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report) {
  StageClock clock;
  SlabThreads* const threads = stage_threads(work, settings, report);
  // the warm start of the next step (§7.4) reads the contacts, integration the velocities
  // and writes the World: side by side on a threaded step, where the store's time counts as
  // integration's
  if (threads == nullptr) {
    work.action_cache.store(work.contacts);
    clock.lap(Stage::SolveNlgs, report.times);
    integrate(work.velocities, settings.solver.dt, world);
  } else {
    side_by_side(
        threads, [&] { work.action_cache.store(work.contacts); },
        [&] { integrate(work.velocities, settings.solver.dt, world); });
  }
  clock.lap(Stage::Integrate, report.times);

  StepDiagnostics of_contacts;
  StepDiagnostics of_spheres;
  side_by_side(
      threads, [&] { measure_contacts(world, work.contacts, of_contacts); },
      [&] { measure_spheres(world, of_spheres); });
  StepDiagnostics diagnostics = join_measures(world, of_contacts, of_spheres);
  diagnostics.max_net_force = report.diagnostics.max_net_force;
  diagnostics.max_cohesive_opening_speed = report.diagnostics.max_cohesive_opening_speed;
  diagnostics.max_cohesive_opening_per_range = report.diagnostics.max_cohesive_opening_per_range;
  report.diagnostics = diagnostics;
  clock.lap(Stage::Analyse, report.times);
}

}  // namespace cdpowder
