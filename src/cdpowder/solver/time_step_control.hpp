// time_step_control.hpp — the adaptive time step (physics.md §6.4, settings.hpp
// TimeStepControl). A rigid contact dynamics step has no stiffness limit: Δt is bounded by
// what the frozen geometry of a step (§3) can represent. Two bounds, both from the velocities
// a step leaves, which the next step starts from:
//   * cohesion: a contact that opens by more than a fraction of d_coh in one step breaks in
//     one or two steps, and the work to break it is no longer F_coh d_coh (§6.4);
//   * motion: a surface that moves a fair part of the candidate skin or of a radius in one
//     step may meet contacts the step's candidate list and frozen normals do not hold.
#pragma once

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/solver/settings.hpp"

namespace cdpowder {

/// How fast the surfaces move after a step, and the length that motion is measured in.
struct SurfaceMotion {
  /// max of |V_P| and, over the spheres, |v| + r|ω| [R/t0]
  double speed = 0.0;
  double smallest_radius = 0.0;  ///< [R]
};

/// The surface motion of `world`: the piston's speed, the spheres' largest surface speed
/// `sphere_speed` (a run takes integrate()'s, SphereMeasures::largest_surface_speed) and their
/// smallest radius.
SurfaceMotion surface_motion(const World& world, double sphere_speed, double smallest_radius);

/// The same with the spheres' speed and radius found in a pass of its own over the spheres.
SurfaceMotion surface_motion(const World& world);

/// Δt of the next step after a step of length `dt`, from the surface motion after it and that
/// step's largest cohesive opening speed (StepDiagnostics::max_cohesive_opening_speed) [t0].
double next_time_step(const TimeStepControl& control, double dt, const SurfaceMotion& motion,
                      double max_cohesive_opening_speed, const ContactLaws& laws, double skin);

/// Δt for repeating a step of length `dt` that opened a contact by `opening_per_range` × d_coh
/// (above max_opening_per_step): scaled to the target opening, at most half of dt, at least
/// dt_min [t0].
double retry_time_step(const TimeStepControl& control, double dt, double opening_per_range);

}  // namespace cdpowder
