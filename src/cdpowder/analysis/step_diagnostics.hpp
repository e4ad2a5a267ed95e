// step_diagnostics.hpp — stage 5 of a step: the accuracy gauges of physics.md §17
// (overlaps, piston force balance) and the state measures every step reports.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/model/world.hpp"

#include <cstddef>

namespace cdpowder {

struct StepDiagnostics {
  std::size_t contacts = 0;           ///< candidate contacts of the step (pairs + walls)
  std::size_t closed_contacts = 0;    ///< contacts with S = R_n + F_c > 0 (force-carrying)
  std::size_t cohesive_contacts = 0;  ///< cohesion-active contacts
  double mean_overlap = 0.0;    ///< mean of max(−g, 0) over closed contacts, after the step [R]
  double max_overlap = 0.0;     ///< largest max(−g, 0) over all contacts, after the step [R]
  double kinetic_energy = 0.0;  ///< Σ ½ m v² + ½ I ω² + ½ M_P V_P² [F_coh R]
  double max_speed = 0.0;       ///< max |v_i| [R/t0]
  double piston_contact_force = 0.0;  ///< Σ R_c→P · e_z, upward push of the spheres [F_coh]
  double piston_imbalance = 0.0;      ///< |Σ R_c→P·e_z − F| / F (0 without a piston load)
};

/// Measures the state after integrate(); `contacts` still holds the step's forces.
StepDiagnostics analyse_step(const World& world, const Contacts& contacts);

}  // namespace cdpowder
