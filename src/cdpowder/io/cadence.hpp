// cadence.hpp — when a periodic output (a time-series row, a snapshot) is due: every K steps,
// or every Δ of simulated time. With an adaptive time step (docs/model.md) a step count
// is no clock, so the time-based cadence is the one that gives evenly spaced records.
#pragma once

#include "cdpowder/model/world.hpp"

#include <cmath>
#include <cstdint>

namespace cdpowder {

class Cadence {
 public:
  /// `every_steps` > 0: due at every multiple of it; `interval` > 0 (it wins): due at the first
  /// step that reaches each multiple of `interval` [t0]; both 0: never.
  Cadence(int every_steps, double interval) : every_steps_(every_steps), interval_(interval) {}

  /// Whether a record is due after the step that left `world`; advances the time cadence.
  bool due(const World& world) {
    if (interval_ > 0.0) {
      // 1e-9 of an interval absorbs the round-off of summed steps (0.1 + 0.1 + … ≠ k × 0.1)
      if (world.time < next_time_ - 1e-9 * interval_) return false;
      next_time_ = (std::floor(world.time / interval_ + 1e-9) + 1.0) * interval_;
      return true;
    }
    return every_steps_ > 0 && world.step % every_steps_ == 0;
  }

  /// Continues a cadence whose last record was due at `time` [t0] (a run continued from a
  /// checkpoint, io/run_outputs.hpp): the next record is due where it would have been had
  /// this object seen that one. A step cadence has no memory.
  void resume_after(double time) {
    if (interval_ > 0.0) next_time_ = (std::floor(time / interval_ + 1e-9) + 1.0) * interval_;
  }

  [[nodiscard]] bool enabled() const { return interval_ > 0.0 || every_steps_ > 0; }

 private:
  int every_steps_;
  double interval_;
  double next_time_ = 0.0;
};

}  // namespace cdpowder
