// blocked_state.cpp — the rest criteria over a sliding window of steps.
#include "cdpowder/run/blocked_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace cdpowder {

BlockedStateDetector::BlockedStateDetector(const BlockedCriteria& criteria, double dt)
    : criteria_(criteria),
      dt_(dt),
      // a fixed-Δt window's steps plus one, so such a run never grows the ring
      ring_(static_cast<std::size_t>(std::max(2.0, std::ceil(criteria.window / dt) + 1.0))) {}

double BlockedStateDetector::mean_force_imbalance() const {
  if (count_ == 0) return 0.0;
  // newest first: the order of the sum is part of the result
  double sum = 0.0;
  for (std::size_t k = count_; k > 0; --k) sum += entry(k - 1).imbalance;
  return sum / static_cast<double>(count_);
}

void BlockedStateDetector::trim() {
  while (count_ > 0 && window_complete(clock_ - entry(0).time)) {
    head_ = (head_ + 1) % ring_.size();
    --count_;
  }
}

void BlockedStateDetector::push(const Entry& e) {
  if (count_ == ring_.size()) {
    std::vector<Entry> larger(2 * ring_.size());
    for (std::size_t k = 0; k < count_; ++k) larger[k] = entry(k);
    ring_.swap(larger);
    head_ = 0;
  }
  ring_[(head_ + count_) % ring_.size()] = e;
  ++count_;
}

double BlockedStateDetector::watched_height(const World& world) {
  const Piston& piston = world.walls.piston;
  if (piston.enabled) return piston.height;
  const std::vector<Vec3>& positions = world.bodies.position;
  double sum = 0.0;
  for (const Vec3& x : positions) sum += x.z();
  return positions.empty() ? 0.0 : sum / static_cast<double>(positions.size());
}

bool BlockedStateDetector::update(const World& world, const StepDiagnostics& d, double dt) {
  const Piston& piston = world.walls.piston;
  clock_ += dt;
  trim();
  // the height at the first held step of the window that ends now: the piston's, or without
  // one the spheres' mean height (a packing creeping down as a whole is not at rest)
  const double height = watched_height(world);
  const double first_height = count_ > 0 ? entry(0).height : height;
  const double drift = std::abs(height - first_height) / std::max(std::abs(height), 1e-300);
  const bool piston_at_rest = !piston.enabled || std::abs(piston.velocity) < criteria_.piston_speed;
  const bool at_rest =
      piston_at_rest && d.rms_speed < criteria_.sphere_speed && drift < criteria_.height_change;
  if (!at_rest) {
    time_held_ = 0.0;
    steps_held_ = 0;
    count_ = 0;
    return false;
  }
  // without a piston there is no imbalance to average: the static solve alone judges the
  // balance (run_loop.cpp)
  push({clock_, height, piston.enabled ? d.piston_imbalance : 0.0});
  time_held_ += dt;
  ++steps_held_;
  return blocked();
}

BlockedStateDetector::Memory BlockedStateDetector::memory() const {
  Memory m{clock_, time_held_, steps_held_, {}};
  m.entries.reserve(count_);
  for (std::size_t k = 0; k < count_; ++k) m.entries.push_back(entry(k));
  return m;
}

void BlockedStateDetector::restore(const Memory& m) {
  bool valid = m.time_held >= 0.0 && m.steps_held >= 0 &&
               static_cast<std::size_t>(m.steps_held) >= m.entries.size();
  for (std::size_t k = 0; k < m.entries.size(); ++k) {
    valid = valid && m.entries[k].time <= m.clock &&
            !window_complete(m.clock - m.entries[k].time) &&
            (k == 0 || m.entries[k - 1].time < m.entries[k].time);
  }
  if (!valid) {
    throw std::invalid_argument(fmt::format(
        "the blocked-state window ({} held steps, {} t0) does not fit a window of {} t0",
        m.entries.size(), m.time_held, criteria_.window));
  }
  clock_ = m.clock;
  time_held_ = m.time_held;
  steps_held_ = m.steps_held;
  if (ring_.size() < m.entries.size() + 1) ring_.resize(m.entries.size() + 1);
  head_ = 0;
  count_ = m.entries.size();
  for (std::size_t k = 0; k < count_; ++k) ring_[k] = m.entries[k];
}

}  // namespace cdpowder
