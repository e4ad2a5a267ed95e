// step_diagnostics.hpp — stage 5 of a step: the accuracy gauges of physics.md §17
// (overlaps, piston force balance) and the state measures every step reports.
#pragma once

#include "cdpowder/analysis/energy_budget.hpp"
#include "cdpowder/analysis/sphere_measures.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/velocity_cache.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/model/world.hpp"

#include <cstddef>
#include <vector>

namespace cdpowder {

struct StepDiagnostics {
  std::size_t contacts = 0;           ///< candidate contacts of the step (pairs + walls)
  std::size_t closed_contacts = 0;    ///< contacts with S = R_n + F_c > 0 (force-carrying)
  std::size_t cohesive_contacts = 0;  ///< cohesion-active contacts
  double mean_overlap = 0.0;    ///< mean of max(−g, 0) over closed contacts, after the step [R]
  double max_overlap = 0.0;     ///< largest max(−g, 0) over all contacts, after the step [R]
  double kinetic_energy = 0.0;  ///< Σ ½ m v² + ½ I ω² + ½ M_P V_P² [F_coh R]
  double max_speed = 0.0;       ///< max |v_i| [R/t0]
  /// mass-weighted RMS sphere speed √(Σ m_i v_i² / Σ m_i): whether the packing flows, which
  /// one rattler does not decide [R/t0]
  double rms_speed = 0.0;
  double piston_contact_force = 0.0;  ///< Σ R_c→P · e_z, upward push of the spheres [F_coh]
  /// |Σ R_c→P·e_z − L| / L with L = F − M_P g_z the piston's load (piston_load; F without
  /// gravity); 0 without a load
  double piston_imbalance = 0.0;
  /// max over free spheres of the net force m|Δv|/Δt + net torque I|Δω|/(Δt r) of the step:
  /// the per-particle force balance of physics.md §17, ≈ 0 in a static packing [F_coh]
  double max_net_force = 0.0;
  /// max over cohesion-active contacts of the normal opening speed V_n > 0 after the step:
  /// a contact opens by V_n Δt per step, which must stay well below d_coh (§6.4)
  /// (CohesiveOpening::speed, analysis/cohesive_opening.hpp) [R/t0]
  double max_cohesive_opening_speed = 0.0;
  /// max over cohesion-active contacts of V_n Δt / d_coh, each with its own d_coh (sphere
  /// pairs and walls may differ); §6.4 asks for ≤ 0.1 [-]
  double max_cohesive_opening_per_range = 0.0;
  /// cohesive bonds the step formed and broke against the step before (counted by the build,
  /// solver/build.hpp; against an empty cache, the first step of a workspace counts every
  /// bond as formed: the run loop leaves a run's first step out of its sums)
  BondChanges bonds;
  /// max over the spheres of |v| + r|ω| after the step (SphereMeasures) [R/t0]
  double largest_surface_speed = 0.0;
  /// integrate() found every sphere's position and velocities finite; false when not
  /// measured, so that find_fault (run/run_fault.hpp) looks for itself
  bool spheres_finite = false;
};

/// Stage 5: the contacts' overlaps from the positions after integrate(), their counts and
/// the piston's contact force, where `contacts` still holds the step's forces.
/// join_measures adds the spheres' measures, which integrate() took on its pass
/// (SphereMeasures), and the piston's share. The two opening gauges come from
/// cohesive_opening (measured before integrate(), where an adaptive Δt decides whether to
/// keep the step). The pairs in pieces fixed by their count (indices_per_piece), side by side
/// on `pieces` when given, each piece's overlaps summed in pair order and the pieces' sums in
/// piece order, then the walls: the same bits on any number of threads.
void measure_contacts(const World& world, const Contacts& contacts, StepDiagnostics& d,
                      PieceRunner* pieces = nullptr);
StepDiagnostics join_measures(const World& world, const StepDiagnostics& of_contacts,
                              const SphereMeasures& of_spheres);

/// Each contact's overlap after the step (Contacts' order, pairs then walls) with
/// measure_contacts' own operations, so that the largest of them is StepDiagnostics::
/// max_overlap to the bit: the contact a fault's overlap came from (run/run_fault.cpp).
std::vector<double> contact_overlaps(const World& world, const Contacts& contacts);

}  // namespace cdpowder
