// blocked_state.cpp — the rest criteria over a window of steps.
#include "cdpowder/experiment/blocked_state.hpp"

#include <cmath>

namespace cdpowder {

BlockedStateDetector::BlockedStateDetector(const BlockedCriteria& criteria, double dt)
    : criteria_(criteria),
      window_steps_(std::max<std::int64_t>(1, std::llround(criteria.window / dt))) {}

bool BlockedStateDetector::update(const World& world, const StepDiagnostics& d) {
  const Piston& piston = world.walls.piston;
  const bool at_rest = piston.enabled && std::abs(piston.velocity) < criteria_.piston_speed &&
                       d.max_speed < criteria_.sphere_speed &&
                       d.piston_imbalance < criteria_.force_balance;
  if (!at_rest) {
    held_ = 0;
    return false;
  }
  if (held_ == 0) window_start_height_ = piston.height;
  const double drift = std::abs(piston.height - window_start_height_) / std::abs(piston.height);
  if (drift >= criteria_.height_change) {
    held_ = 0;
    return false;
  }
  ++held_;
  return held_ >= window_steps_;
}

}  // namespace cdpowder
