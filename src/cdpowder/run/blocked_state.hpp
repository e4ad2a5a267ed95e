// blocked_state.hpp — has the piston come to rest? (physics.md §9; Bartels et al. call
// the static end state "blocked"). The packing is blocked once, over a sliding window of
// simulated time (BlockedCriteria::window; with a fixed Δt, window/Δt steps),
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
  /// `dt`: the step length update(world, d) assumes (a fixed-Δt run's Δt).
  BlockedStateDetector(const BlockedCriteria& criteria, double dt);

  /// Feeds the state after a step of length `dt` [t0]; returns true once a whole window
  /// (BlockedCriteria::window of simulated time) meets the criteria.
  bool update(const World& world, const StepDiagnostics& diagnostics, double dt);

  bool update(const World& world, const StepDiagnostics& diagnostics) {
    return update(world, diagnostics, dt_);
  }

  /// What the last update returned: a whole window met the per-step criteria and the
  /// window mean of the force imbalance is below its threshold. A pure function of the
  /// memory, so a run continued from a state file can ask it again.
  [[nodiscard]] bool blocked() const {
    return at_rest_for_window() && mean_force_imbalance() < criteria_.force_balance;
  }

  /// A whole window has met the per-step criteria (speeds and height drift); only the
  /// force balance may be missing.
  [[nodiscard]] bool at_rest_for_window() const { return window_complete(time_held_); }

  /// Whether `elapsed` simulated time fills a window: elapsed ≥ window up to a relative
  /// 1e-9, so that with a fixed Δt a window is exactly window/Δt steps (sums of Δt carry
  /// round-off; a step is ≥ 1e-6 of the window).
  [[nodiscard]] bool window_complete(double elapsed) const {
    return elapsed >= criteria_.window * (1.0 - kWindowSlack);
  }

  /// Steps in a row that met the per-step criteria (speeds and height drift).
  [[nodiscard]] std::int64_t steps_held() const { return steps_held_; }

  /// Mean piston force imbalance over the held steps of the last window (0 if none): a plain
  /// mean over steps, so with an adaptive Δt short steps weigh as much as long ones.
  [[nodiscard]] double mean_force_imbalance() const;

  /// The height whose drift the window bounds: the piston's, or without a piston the spheres'
  /// mean height [R].
  [[nodiscard]] static double watched_height(const World& world);

  /// One held step in the window: the detector's clock at its end, the watched height, the
  /// piston's imbalance (0 without a piston).
  struct Entry {
    double time = 0.0;
    double height = 0.0;
    double imbalance = 0.0;
  };

  /// What the detector remembers between steps, as a state file stores it.
  struct Memory {
    double clock = 0.0;      ///< simulated time fed so far [t0]
    double time_held = 0.0;  ///< duration of the current run of held steps [t0]
    std::int64_t steps_held = 0;
    std::vector<Entry> entries;  ///< held steps of the last window, oldest first
  };

  [[nodiscard]] Memory memory() const;

  /// Continues from a saved memory. Throws std::invalid_argument when it cannot belong to
  /// this detector (negative counts, entries out of order or older than a window).
  void restore(const Memory& memory);

 private:
  static constexpr double kWindowSlack = 1e-9;

  /// Drops entries older than a window, keeping those of the window that ends now.
  void trim();
  void push(const Entry& entry);

  [[nodiscard]] const Entry& entry(std::size_t k) const {  // k = 0: oldest
    return ring_[(head_ + k) % ring_.size()];
  }

  BlockedCriteria criteria_;
  double dt_;
  double clock_ = 0.0;
  double time_held_ = 0.0;
  std::int64_t steps_held_ = 0;
  /// Held steps of the last window, a ring (head_ = oldest, count_ entries). It grows when a
  /// window holds more steps than ever before (an adaptive Δt that shrank), never per step.
  std::vector<Entry> ring_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
};

}  // namespace cdpowder
