// blocked_state.cpp — the rest criteria over a sliding window of steps.
#include "cdpowder/experiment/blocked_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace cdpowder {

BlockedStateDetector::BlockedStateDetector(const BlockedCriteria& criteria, double dt)
    : criteria_(criteria),
      window_steps_(std::max<std::int64_t>(1, std::llround(criteria.window / dt))),
      heights_(static_cast<std::size_t>(window_steps_), 0.0),
      imbalances_(static_cast<std::size_t>(window_steps_), 0.0) {}

double BlockedStateDetector::mean_force_imbalance() const {
  const std::int64_t n = std::min(held_, window_steps_);
  if (n == 0) return 0.0;
  // the ring holds the last window_steps_ steps; the last n of them are the held ones
  double sum = 0.0;
  for (std::int64_t k = 0; k < n; ++k) {
    sum += imbalances_[static_cast<std::size_t>((steps_seen_ - 1 - k) % window_steps_)];
  }
  return sum / static_cast<double>(n);
}

void BlockedStateDetector::restore(const Memory& memory) {
  const auto n = static_cast<std::size_t>(window_steps_);
  if (memory.heights.size() != n || memory.imbalances.size() != n || memory.held < 0 ||
      memory.steps_seen < 0) {
    throw std::invalid_argument(
        fmt::format("the blocked-state window holds {} steps, this run's window {} steps",
                    memory.heights.size(), window_steps_));
  }
  held_ = memory.held;
  steps_seen_ = memory.steps_seen;
  heights_ = memory.heights;
  imbalances_ = memory.imbalances;
}

bool BlockedStateDetector::update(const World& world, const StepDiagnostics& d) {
  const Piston& piston = world.walls.piston;
  const auto slot = static_cast<std::size_t>(steps_seen_ % window_steps_);
  // the height window_steps_ − 1 steps ago, i.e. at the first step of the window that ends
  // now (read before this step overwrites the slot)
  const std::int64_t first = steps_seen_ - std::min(held_, window_steps_ - 1);
  const double first_height = first < steps_seen_
                                  ? heights_[static_cast<std::size_t>(first % window_steps_)]
                                  : piston.height;
  heights_[slot] = piston.height;
  imbalances_[slot] = d.piston_imbalance;
  ++steps_seen_;

  const double drift = std::abs(piston.height - first_height) / std::abs(piston.height);
  const bool at_rest = piston.enabled && std::abs(piston.velocity) < criteria_.piston_speed &&
                       d.rms_speed < criteria_.sphere_speed && drift < criteria_.height_change;
  if (!at_rest) {
    held_ = 0;
    return false;
  }
  ++held_;
  return held_ >= window_steps_ && mean_force_imbalance() < criteria_.force_balance;
}

}  // namespace cdpowder
