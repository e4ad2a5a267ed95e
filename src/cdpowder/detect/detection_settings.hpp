// detection_settings.hpp — what stage 1 (detect_contacts.hpp) reads of a step's settings: the
// reach of cohesion, the time step and the two margins of the candidate search. The solver's
// StepSettings gives them (StepSettings::detection(), solver/settings.hpp).
#pragma once

namespace cdpowder {

struct DetectionSettings {
  double cohesion_range = 0.0;  ///< the larger of the sphere–sphere and sphere–wall d_coh [R]
  double dt = 0.0;              ///< Δt of the step [t0]
  double skin = 0.0;            ///< extra candidate distance beyond max(d_coh, 2 v_max Δt) [R]
  double verlet_margin = 0.0;   ///< candidate list's reach beyond the candidate gap [R]
};

}  // namespace cdpowder
