// progress.hpp — the live progress line of long runs on stderr: simulated time, piston
// height, porosity, passes per step, contacts, elapsed and estimated remaining wall time.
// On a terminal redrawn in place at most every `interval` seconds, cut to its width; when
// stderr is not a terminal (a log file), a plain line at most every 30 s. Silent when quiet.
#pragma once

#include "cdpowder/solver/step.hpp"

#include <chrono>
#include <cstdint>

namespace cdpowder::app {

class ProgressLine {
 public:
  explicit ProgressLine(bool quiet, double interval_seconds = 0.5);

  /// fraction: share of the run's time budget done (0..1).
  void update(const World& world, const StepReport& report, double fraction);

  /// Ends the line (newline) if anything was drawn.
  void finish();

 private:
  bool quiet_;
  double interval_;
  int columns_;  ///< the terminal's width, 0 when stderr is not a terminal
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_ = start_;
  std::int64_t passes_since_draw_ = 0;
  std::int64_t steps_since_draw_ = 0;
};

}  // namespace cdpowder::app
