// summary.hpp — summary.json: the measurements at the end of a run with their accuracy
// gauges (physics.md §17), how the run went, and everything needed to rerun it.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/experiment/run_loop.hpp"
#include "cdpowder/model/world.hpp"

#include <string>

namespace cdpowder {

/// JSON text of the summary: porosity, piston state and force balance, σ, σ⁺, σ⁻ (3×3,
/// [F_coh/R²]) and the same divided by the applied pressure, contact counts and
/// coordination, overlaps, kinetic energy, steps and sweeps, blocked, wall time per stage,
/// the fully resolved scene, seed, version and commit.
std::string summary_json(const Scene& scene, const World& world, const Contacts& contacts,
                         const RunResult& result);

}  // namespace cdpowder
