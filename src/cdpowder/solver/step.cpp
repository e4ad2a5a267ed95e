// step.cpp — the time step as a table of contents. The stages run in this order only;
// each reads what the one before it wrote. Contact geometry is frozen after stage 1 (§3).
#include "cdpowder/solver/step.hpp"

#include "cdpowder/analysis/cohesive_opening.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/integrate.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"

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

CarriedActions last_step_actions(const StepWorkspace& work) {
  if (work.last_step_in_contacts) {
    return {carried_pairs(work.contacts), carried_walls(work.contacts)};
  }
  const KeyedContacts& cached = work.action_cache.last();
  return {carried_pairs(cached), carried_walls(cached)};
}

void release_step_scratch(StepWorkspace& work) {
  work.candidates = CandidateList{};
  work.detection = DetectionScratch{};
  // the velocity cache: every build fills it anew from the World (64 bytes a sphere)
  work.velocities.spheres = {};
  // the cache holds the step before the committed one until the next begin_step takes the
  // committed contacts (ActionCache::take): nothing reads it until then (73 bytes a contact)
  if (work.last_step_in_contacts) work.action_cache = ActionCache{};
  NlgsWorkspace& solver = work.solver;
  solver.accelerator = AndersonAccelerator(solver.accelerator.depth());
  solver.start = {};
  solver.kinematic = KinematicChange{};
  solver.coloured = ColouredPass{};
  solver.order = TileOrder{};
  solver.range_sums = {};
}

void take_last_step(StepWorkspace& work, PieceRunner* pieces) {
  if (!work.last_step_in_contacts) return;
  work.action_cache.take(work.contacts, pieces);
  work.last_step_in_contacts = false;
}

namespace {

/// The workers of the stages around a solve: those of the solve when it ran on them
/// (`threaded`), nullptr otherwise. A step the ThreadChoice keeps on one thread (the second
/// core was slower lately) keeps its other stages there too.
TileThreads* step_threads(StepWorkspace& work, const StepSettings& settings, bool threaded) {
  const int threads = solve_threads(settings.solver);
  return threaded && threads >= 2 ? work.solver.threads.get(threads) : nullptr;
}

}  // namespace

StepReport begin_step(World& world, StepWorkspace& work, const StepSettings& settings) {
  StepReport report;
  report.dt = settings.solver.dt;
  StageClock clock;
  // the last step's contacts become the warm-start cache (§7.4) before detection refills
  // work.contacts: a swap of six arrays (nanoseconds), timed with the detection that needs
  // them out of the way. A step solved again with a shorter Δt finds them taken already.
  // on the threads where the last step's solve was (a step too small to cut, or one the
  // ThreadChoice keeps on one thread, keeps these stages there too)
  TileThreads* const threads = step_threads(work, settings, work.threaded);
  take_last_step(work, threads);

  detect_contacts(world, settings.detection(), work.grid, work.contacts, &work.candidates, threads,
                  &work.detection);
  clock.lap(Stage::DetectContacts, report.times);

  report.diagnostics.bonds = build_local_problems(world, settings, work.action_cache, work.contacts,
                                                  work.velocities, threads, &work.build);
  clock.lap(Stage::BuildLocalProblems, report.times);
  return report;
}

void finish_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report) {
  solve_step(world, work, settings, report);
  commit_step(world, work, settings, report);
}

void solve_step(const World& world, StepWorkspace& work, const StepSettings& settings,
                StepReport& report) {
  StageClock clock;
  const double reference_force = settings.laws.spheres.cohesion_force;
  NlgsWorkspace& solver = work.solver;
  // on the threads of the last step's solve, as the detection before it
  assign_tiles(world.bodies.position, world.box, world.bodies.max_radius(),
               settings.solver.tile_width, work.contacts, solver.tiles,
               step_threads(work, settings, work.threaded));
  report.solver = solve_nlgs(work.contacts, work.velocities, settings.solver, reference_force,
                             solver, &solver.tiles);
  work.threaded = report.solver.threaded;
  clock.lap(Stage::SolveNlgs, report.times);

  // the opening gauge, on both threads of a threaded step
  TileThreads* const threads = step_threads(work, settings, report.solver.threaded);
  const CohesiveOpening opening = cohesive_opening(world, work.contacts, work.velocities,
                                                   settings.laws, settings.solver.dt, threads);
  report.diagnostics.max_cohesive_opening_speed = opening.speed;
  report.diagnostics.max_cohesive_opening_per_range = opening.per_range;
  clock.lap(Stage::Analyse, report.times);
}

void commit_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report) {
  StageClock clock;
  // integration reads the velocities, writes the World and measures the spheres on its pass
  // (SphereMeasures); the contacts' overlaps need its new positions. The contacts stay where
  // they are: the next begin_step takes them for its warm start (§7.4).
  // in pieces fixed by the count on the threads of the step's solve, their sums added in piece
  // order: the same bits on any number of threads
  TileThreads* const threads = step_threads(work, settings, work.threaded);
  const SphereMeasures of_spheres = integrate(work.velocities, settings.solver.dt, world, threads);
  clock.lap(Stage::Integrate, report.times);
  StepDiagnostics of_contacts;
  measure_contacts(world, work.contacts, of_contacts, threads);
  work.last_step_in_contacts = true;
  StepDiagnostics diagnostics = join_measures(world, of_contacts, of_spheres);
  diagnostics.max_cohesive_opening_speed = report.diagnostics.max_cohesive_opening_speed;
  diagnostics.max_cohesive_opening_per_range = report.diagnostics.max_cohesive_opening_per_range;
  diagnostics.bonds = report.diagnostics.bonds;
  report.diagnostics = diagnostics;
  clock.lap(Stage::Analyse, report.times);
}

}  // namespace cdpowder
