// step.cpp — the time step as a table of contents. The stages run in this order only;
// each reads what the one before it wrote. Contact geometry is frozen after stage 1 (§3).
#include "cdpowder/solver/step.hpp"

#include "cdpowder/analysis/cohesive_opening.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/build.hpp"
#include "cdpowder/solver/integrate.hpp"
#include "cdpowder/solver/slabs.hpp"

#include <chrono>

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

  detect_contacts(world, settings.detection(), work.grid, work.contacts, &work.candidates);
  clock.lap(Stage::DetectContacts, report.times);

  build_local_problems(world, settings, work.action_cache, work.contacts, work.velocities);
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
  cut_into_slabs(world.bodies.position, work.contacts, solver.slab, solver.slab_scratch);
  report.solver = solve_nlgs(work.contacts, work.velocities, settings.solver, reference_force,
                             solver, solver.slab);
  clock.lap(Stage::SolveNlgs, report.times);

  const CohesiveOpening opening =
      cohesive_opening(world, work.contacts, work.velocities, settings.laws, settings.solver.dt);
  report.diagnostics.max_cohesive_opening_speed = opening.speed;
  report.diagnostics.max_cohesive_opening_per_range = opening.per_range;
  clock.lap(Stage::Analyse, report.times);
}

void commit_step(World& world, StepWorkspace& work, const StepSettings& settings,
                 StepReport& report) {
  StageClock clock;
  work.action_cache.store(work.contacts);  // warm start of the next step (§7.4)
  clock.lap(Stage::SolveNlgs, report.times);

  const double net_force = net_force_of_step(world.bodies, work.velocities);
  integrate(work.velocities, settings.solver.dt, world);
  clock.lap(Stage::Integrate, report.times);

  StepDiagnostics diagnostics = analyse_step(world, work.contacts);
  diagnostics.max_net_force = net_force;
  diagnostics.max_cohesive_opening_speed = report.diagnostics.max_cohesive_opening_speed;
  diagnostics.max_cohesive_opening_per_range = report.diagnostics.max_cohesive_opening_per_range;
  report.diagnostics = diagnostics;
  clock.lap(Stage::Analyse, report.times);
}

}  // namespace cdpowder
