// timeseries.cpp — rows of the per-step diagnostics.
#include "cdpowder/io/timeseries.hpp"

#include "cdpowder/analysis/porosity.hpp"

#include <fmt/format.h>

namespace cdpowder {

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path, const std::string& header,
                                   Cadence cadence)
    : file_(path), cadence_(cadence) {
  file_.write(header);
  file_.write(
      "step,time,piston_height,piston_velocity,porosity,kinetic_energy,sweeps,"
      "converged,residual,error_estimate,contacts,closed_contacts,mean_overlap,"
      "max_overlap,piston_imbalance,max_net_force,max_cohesive_opening_speed,dt\n");
}

void TimeseriesWriter::record(const World& world, const StepReport& r, bool force) {
  if (world.step == last_step_) return;
  if (!cadence_.due(world) && !force) return;
  last_step_ = world.step;
  const StepDiagnostics& d = r.diagnostics;
  file_.write(fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", world.step,
                          world.time, world.walls.piston.height, world.walls.piston.velocity,
                          porosity(world), d.kinetic_energy, r.solver.sweeps,
                          r.solver.converged ? 1 : 0, r.solver.residual, r.solver.error_estimate,
                          d.contacts, d.closed_contacts, d.mean_overlap, d.max_overlap,
                          d.piston_imbalance, d.max_net_force, d.max_cohesive_opening_speed, r.dt));
}

}  // namespace cdpowder
