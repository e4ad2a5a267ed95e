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
/// the fully resolved scene, seed, version and commit. `initial_porosity` is that of the
/// starting packing (the deposit before compaction).
std::string summary_json(const Scene& scene, const World& world, const Contacts& contacts,
                         const RunResult& result, double initial_porosity);

/// JSON text of a deposit's summary: porosity and height of the deposit (physics.md §8.2),
/// sphere count, the resolved scene, the deposition seed, version and commit.
std::string deposit_summary_json(const Scene& scene, const World& world);

}  // namespace cdpowder
