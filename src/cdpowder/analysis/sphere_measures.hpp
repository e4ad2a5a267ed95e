// sphere_measures.hpp — what a step's pass over the spheres measures: energies, speeds,
// the net force, the fastest surface and whether the state is finite. integrate()
// (solver/integrate.hpp) takes them while it moves the spheres.
#pragma once

namespace cdpowder {

/// What integrate() measures on its pass over the spheres. Each value is what a pass of its
/// own over the World after the step (or, for the net force, over the velocities before and
/// after) would give, to the last bit: the sums add the spheres in index order. (Only the
/// sign of a NaN energy may differ, on a state that is a fault anyway.) One pass
/// instead of five (the energies and speeds, the net force, the next Δt's surface speed and
/// the finiteness check each read every sphere once;
/// docs/lab/2026-11-27-one-pass-over-the-spheres.md).
struct SphereMeasures {
  /// Σ ½ m v² + ½ I ω² over the free spheres, without the piston [F_coh R]
  double kinetic_energy = 0.0;
  double max_speed = 0.0;  ///< max |v_i| over the free spheres [R/t0]
  /// mass-weighted RMS speed √(Σ m_i v_i² / Σ m_i) of the free spheres [R/t0]
  double rms_speed = 0.0;
  /// max over free spheres of m|v* − v|/Δt + I|ω* − ω|/(Δt r): the largest net force and
  /// torque / radius the step's contact forces and loads left on a sphere (physics.md §17)
  /// [F_coh]
  double max_net_force = 0.0;
  /// max over all spheres of |v| + r|ω| after the step: how far a surface moves per unit
  /// time, which bounds the next Δt (solver/time_step_control.hpp) [R/t0]
  double largest_surface_speed = 0.0;
  /// every sphere's position, velocity and angular velocity is finite after the step
  bool finite = true;
};

}  // namespace cdpowder
