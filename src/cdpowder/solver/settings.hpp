// settings.hpp — the inputs of one time step that are not physical state:
// Δt, the NLGS stopping rule and visiting order, detection skin, the contact laws.
#pragma once

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/core/cpu_budget.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/detect/detection_settings.hpp"

#include <algorithm>
#include <cstdint>

namespace cdpowder {

/// How the NLGS decides that a step's contact problem is solved (physics.md §7.2–7.3, §17).
enum class StoppingRule {
  /// Default. The largest force correction of a pass (the natural-map residual of the
  /// contact laws, torques divided by r_eff) relative to the force scale, divided by
  /// (1 − ρ) where ρ is the measured contraction per pass: an estimate of the remaining
  /// force error rather than of the last change (§17).
  Residual,
  /// The group's global test ⟨|ΔR|⟩ ≤ α ⟨|R|⟩ ([S+12] criterion II). Kept for comparison;
  /// it stops early on slowly converging, piston-loaded problems (§17).
  RelativeChange,
};

/// What the kinematic rule (SolverSettings::kinematic_tolerance, physics.md §7.3) measures of
/// a pass's change of the spheres' surface velocities u(Δv, Δω).
enum class KinematicNorm {
  /// Default. The largest change over the spheres. A maximum over N spheres grows with N (an
  /// extreme of more samples), so a wider cell takes more passes a step for the same κ
  /// (docs/lab/2026-11-29-what-grows-the-passes.md).
  Max,
  /// The RMS change over the spheres, √(Σ u(Δv, Δω)² / N): relative to the RMS speed it is a
  /// relative change of the velocity field, which does not grow with N. The same κ is a
  /// looser test than with Max (the RMS is below the largest); κ/10 takes about as many passes
  /// as Max at the paper's 1 015 spheres.
  Rms,
};

/// Order in which a pass visits the contacts (physics.md §7.1).
enum class VisitOrder {
  /// A fresh seeded permutation of blocks of contacts every step (≥ 1024 blocks, ≤ 256
  /// contacts each), kept for all passes of the step (default). Random across steps, so no
  /// direction is preferred; a stationary
  /// pass map within the step, which Anderson acceleration needs; blocks of contacts that
  /// share spheres, which keeps large systems cache friendly.
  RandomEachStep,
  /// A fresh seeded permutation every pass: the group's choice [UK03]. Use it with
  /// acceleration_depth = 0 (plain NLGS), which reproduces the paper's algorithm.
  RandomEachPass,
  Fixed,  ///< storage order (sorted by body indices); for tests and benchmarks
};

/// How a pass solves the contacts (docs/lab/2026-11-25-coloured-kernel.md).
enum class PassKernel {
  /// One contact after the other in the visiting order (two independent ones side by side);
  /// the order is a permutation of blocks of contacts.
  Scalar,
  /// Default. Sphere–sphere contacts graph-coloured each step, each colour solved in
  /// batches of 4 side by side (the same arithmetic per contact), bottom-wall contacts too;
  /// overflow and piston contacts one by one; the colours visited in a random order per step
  /// (per pass with random_each_pass, storage order with fixed). Converges differently from
  /// "scalar" (equally well: the accuracy gate of docs/lab/2026-11-25-coloured-kernel-default.md)
  /// and ≈ 1.3× faster per pass.
  Coloured,
};

/// Adaptive time step (physics.md §6.4): after every step the next Δt is the largest that
/// keeps, at the velocities the step left, (1) every cohesion-active contact's normal
/// opening per step below opening_per_step × d_coh, and (2) every sphere's surface and the
/// piston moving less than displacement_per_step × min(R_min, skin) per step; it grows by at
/// most `growth` per step and stays within [dt_min, dt_max] (solver/time_step_control.hpp).
/// A step that opened a contact by more than max_opening_per_step × d_coh is undone and
/// repeated with a Δt scaled to the target (run/run_loop.cpp).
struct TimeStepControl {
  bool adaptive = false;  ///< off: every step is SolverSettings::dt
  double dt_min = 1e-4;   ///< [t0]
  /// [t0]; 0.02 and 0.03 passed the accuracy gate at (0,0) and (1,1), 0.05 shifted the (1,1)
  /// stress split by 2.1 standard errors (docs/lab/2026-11-25-accuracy-gate.md, "Changes gated")
  double dt_max = 0.03;
  double opening_per_step = 0.05;  ///< target of max V_n Δt / d_coh; the §17 gauge allows 0.1
  /// A step whose largest cohesive opening exceeds this × d_coh is undone and solved again
  /// with a shorter Δt (a contact that starts to open at once gives no warning to the
  /// target above) [-]
  double max_opening_per_step = 0.1;
  double displacement_per_step = 0.2;  ///< fraction of min(R_min, skin) a surface may move
  double growth = 1.2;                 ///< largest ratio of two consecutive steps
};

/// Largest solver.threads: a sanity bound, not a tested size (the budget holds a count to the
/// cores the process may use; core/cpu_budget.hpp).
inline constexpr int kMaxSolverThreads = 1024;

/// Largest solver.acceleration_depth: the Anderson fit is a kMaxAndersonDepth ×
/// kMaxAndersonDepth problem at most (solver/nlgs/anderson.hpp).
inline constexpr int kMaxAndersonDepth = 16;

struct SolverSettings {
  double dt = 0.01;  ///< Δt [t0] (physics.md §3); the first step's Δt when adaptive
  TimeStepControl time_step;
  double tolerance = 1e-6;  ///< see StoppingRule [-]
  /// Largest factor 1/(1 − ρ) by which the Residual rule scales the residual into an error
  /// estimate. ρ is capped at 0.999, so the default 1000 leaves the rule as it was; a smaller
  /// bound stops slowly contracting steps (ρ → 1 at the compaction front) sooner [-].
  double max_error_amplification = 1000.0;
  /// κ of the kinematic rule, a second way to finish a step (physics.md §7.3): the step also
  /// stops when the largest change of a sphere's surface velocity over the last pass,
  /// / (1 − ρ) with ρ its contraction per pass, is at most κ × the RMS surface speed of the
  /// spheres, and the same holds for the piston against its own speed. Forces of a rigid
  /// packing are not unique (§12.4): at the compaction front the force residual stalls while
  /// the velocities no longer move, and the velocities are what a step passes on. Relative,
  /// so a packing at rest is left to the residual rule. 0 = off [-]
  double kinematic_tolerance = 0.0;
  KinematicNorm kinematic_norm = KinematicNorm::Max;  ///< what the kinematic rule measures
  int min_passes = 3;                                 ///< never stop before this many passes
  int max_passes = 2000;  ///< N_max; a capped step is flagged in its report
  StoppingRule stopping_rule = StoppingRule::Residual;
  VisitOrder visit_order = VisitOrder::RandomEachStep;
  PassKernel kernel = PassKernel::Coloured;
  /// Threads of the coloured kernel's solve: the tiles of a phase (solver/nlgs/tiles.hpp) are
  /// solved side by side, the same bits for any count. 0 takes every core the process may
  /// use; any count is held to that budget (core/cpu_budget.hpp, solve_threads). The scene
  /// reader rejects more than one with the scalar kernel; solve_nlgs runs that on one thread.
  int threads = 1;
  /// Width the tiles of a step aim at (solver/nlgs/tiles.hpp); 0: kTileWidthRadii × R_max. It
  /// fixes the visiting order, so the results depend on it [R]
  double tile_width = 0.0;
  int acceleration_depth = 5;  ///< Anderson acceleration history m; 0 = plain NLGS (anderson.hpp)
  /// Passes between two mixing steps: the accelerated map is k passes in a row. The mixing
  /// moves ≈ 2m + 10 doubles per force component, about a pass's cost on a paper-size
  /// packing, so k > 1 trades fewer mixings against the acceleration per pass.
  int acceleration_interval = 3;
  bool warm_start = true;  ///< start from last step's actions (§7.4)
  double skin = 0.05;      ///< extra candidate distance beyond max(d_coh, 2 v_max Δt) [R]
  /// extra distance of the candidate list (detect/candidate_list.hpp) beyond the candidate
  /// gap: the list is rebuilt once a sphere has moved about half of it; 0 rebuilds every
  /// step. Speed only: the contacts of every step are the same for any value [R]
  double verlet_margin = 0.2;
  std::uint64_t seed = 1;  ///< seed of the pass-order stream
  /// Asked after every pass (not a scene key; the run loop sets it): true ends the solve
  /// there, on that pass's output, with SolverStats::stopped. Null: never asked.
  const StopRequest* stop_request = nullptr;
};

/// The threads a step's solve runs on: the setting within the process's CPU budget
/// (budgeted_threads); one for the scalar kernel.
inline int solve_threads(const SolverSettings& settings) {
  if (settings.kernel != PassKernel::Coloured) return 1;
  return budgeted_threads(settings.threads);
}

struct StepSettings {
  SolverSettings solver;
  ContactLaws laws;

  /// What stage 1 reads (detect/detect_contacts.hpp).
  [[nodiscard]] DetectionSettings detection() const {
    return {std::max(laws.spheres.cohesion_range, laws.walls.cohesion_range), solver.dt,
            solver.skin, solver.verlet_margin};
  }
};

}  // namespace cdpowder
