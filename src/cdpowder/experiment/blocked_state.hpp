// blocked_state.hpp — has the piston come to rest? (physics.md §9; Bartels et al. call
// the static end state "blocked"). All criteria of BlockedCriteria must hold at every step
// of a window; the piston height may drift by at most height_change × Z_P over it.
#pragma once

#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/config/scene.hpp"
#include "cdpowder/model/world.hpp"

#include <cstdint>

namespace cdpowder {

class BlockedStateDetector {
 public:
  BlockedStateDetector(const BlockedCriteria& criteria, double dt);

  /// Feeds the state after a step; returns true once the window is complete.
  bool update(const World& world, const StepDiagnostics& diagnostics);

  /// Steps the criteria have held in a row.
  [[nodiscard]] std::int64_t steps_held() const { return held_; }

 private:
  BlockedCriteria criteria_;
  std::int64_t window_steps_;
  std::int64_t held_ = 0;
  double window_start_height_ = 0.0;
};

}  // namespace cdpowder
