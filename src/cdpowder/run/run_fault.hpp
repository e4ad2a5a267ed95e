// run_fault.hpp — a state no physical run can reach, caught the step it appears: a
// non-finite position or velocity (a NaN spreads through the passes within a step and would
// be reported steps later, or never), an overlap far beyond the rigid contact's (physics.md
// §17 asks for a mean of 1e-3 R), a piston through the bottom wall, or a porosity outside
// (0, 1). The run loop stops at the first one (run_loop.cpp) and the caller reports it.
#pragma once

#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/model/world.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace cdpowder {

/// What went wrong, where and when. `message` is one line naming all of it.
struct RunFault {
  std::string quantity;     ///< "position", "velocity", "angular velocity", "overlap", …
  std::int64_t body = -1;   ///< the sphere (its index), −1 for the piston or the packing
  std::int64_t other = -1;  ///< the other sphere of an overlapping pair, −1 otherwise
  std::int64_t step = 0;    ///< the step after which it was found (World::step)
  double time = 0.0;        ///< [t0]
  double value = 0.0;       ///< the offending value (NaN for a non-finite one)
  std::string message;
};

/// The bounds a step is checked against (RunConfig::max_overlap and the constant grain
/// volume, computed once per run).
struct FaultLimits {
  double max_overlap = 0.1;   ///< largest overlap of any contact after a step [R]
  double grain_volume = 0.0;  ///< Σ (4/3) π R_i³, for the porosity under the piston [R³]
};

/// The first fault of the state after a step, or nothing. Cheap enough for every step: one
/// pass over the positions and velocities (non-finite values), the step's largest overlap
/// and the piston; the overlapping pair is looked up only when the bound is exceeded.
std::optional<RunFault> find_fault(const World& world, const Contacts& contacts,
                                   const StepDiagnostics& diagnostics, const FaultLimits& limits);

}  // namespace cdpowder
