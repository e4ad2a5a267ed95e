// blocked_state.hpp — has the piston come to rest? (physics.md §9; Bartels et al. call
// the static end state "blocked"). The packing is blocked once, over a sliding window of
// steps (BlockedCriteria::window),
//   * at every step |V_P| and the spheres' mass-weighted RMS speed stay below their
//     thresholds (RMS, not the fastest sphere: a rattler flying through a pore of a
//     resting packing, or a sphere rolling freely on a neighbour, does not make it flow;
//     measured on paper-scale packings at rest: single spheres at up to 0.1 R/t0),
//   * the piston height drifts by at most height_change × Z_P from the window's first step,
//   * the window mean of the piston's force imbalance |Σ R·e_z − F|/F is below
//     force_balance.
// The force balance is averaged (Shaebani, Unger & Kertész 2009 average their stopping test
// too): at a finite solver tolerance a resting piston's per-step imbalance is solver noise
// (measured at tolerance 1e-3 on the paper's (1,1) packing at rest: median 2e-3, single
// steps up to 3e-2), so single noisy steps must not restart the window. The mean is of
// the absolute imbalance, so it does not average the noise away: its threshold bounds the
// noise's typical size. When a whole window is at rest but that mean stays too high, the
// run loop tests the balance on a static solve instead (run_loop.cpp).
#pragma once

#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/config/scene.hpp"
#include "cdpowder/model/world.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

class BlockedStateDetector {
 public:
  BlockedStateDetector(const BlockedCriteria& criteria, double dt);

  /// Feeds the state after a step; returns true once a whole window meets the criteria.
  bool update(const World& world, const StepDiagnostics& diagnostics);

  /// A whole window has met the per-step criteria (speeds and height drift); only the
  /// force balance may be missing.
  [[nodiscard]] bool at_rest_for_window() const { return held_ >= window_steps_; }

  /// Steps of one window.
  [[nodiscard]] std::int64_t window_steps() const { return window_steps_; }

  /// Steps in a row that met the per-step criteria (speeds and height drift).
  [[nodiscard]] std::int64_t steps_held() const { return held_; }

  /// Mean piston force imbalance over the last min(steps_held, window) steps (0 if none).
  [[nodiscard]] double mean_force_imbalance() const;

  /// What the detector remembers between steps, as a state file stores it.
  struct Memory {
    std::int64_t held = 0;
    std::int64_t steps_seen = 0;
    std::vector<double> heights;     ///< ring of window_steps() piston heights [R]
    std::vector<double> imbalances;  ///< ring of window_steps() force imbalances [-]
  };

  [[nodiscard]] Memory memory() const { return {held_, steps_seen_, heights_, imbalances_}; }

  /// Continues from a saved memory. Throws std::invalid_argument when its rings are not
  /// window_steps() long (the window or Δt differ from the run that saved it).
  void restore(const Memory& memory);

 private:
  BlockedCriteria criteria_;
  std::int64_t window_steps_;
  std::int64_t held_ = 0;
  /// Piston height and force imbalance of the last window_steps_ steps, a ring indexed by
  /// the step count modulo window_steps_.
  std::vector<double> heights_;
  std::vector<double> imbalances_;
  std::int64_t steps_seen_ = 0;
};

}  // namespace cdpowder
