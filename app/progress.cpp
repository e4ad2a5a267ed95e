// progress.cpp — formatting the progress line.
#include "progress.hpp"

#include "clock_text.hpp"

#include "cdpowder/analysis/porosity.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace cdpowder::app {

ProgressLine::ProgressLine(bool quiet, double interval_seconds)
    : quiet_(quiet), interval_(interval_seconds) {}

void ProgressLine::update(const World& world, const StepReport& report, double fraction) {
  if (quiet_) return;
  sweeps_since_draw_ += report.solver.sweeps;
  ++steps_since_draw_;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_ && fraction < 1.0) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  // the budget is the maximum duration: for until-blocked runs this is an upper bound
  const std::string remaining =
      fraction > 0.0 ? clock_text(elapsed * (1.0 - fraction) / fraction) : "?";
  const double sweeps = static_cast<double>(sweeps_since_draw_) /
                        static_cast<double>(std::max<std::int64_t>(1, steps_since_draw_));
  std::string line = fmt::format("t={:.4g}", world.time);
  if (world.walls.piston.enabled) {
    line += fmt::format(" Z_P={:.4g} E={:.4f}", world.walls.piston.height, porosity(world));
  }
  line += fmt::format(" sweeps/step={:.1f} contacts={} elapsed {} remaining <= {}", sweeps,
                      report.diagnostics.contacts, clock_text(elapsed), remaining);
  std::fprintf(stderr, "\r%-100s", line.c_str());
  std::fflush(stderr);
  drawn_ = true;
  sweeps_since_draw_ = 0;
  steps_since_draw_ = 0;
}

void ProgressLine::finish() {
  if (drawn_) std::fprintf(stderr, "\n");
  drawn_ = false;
}

}  // namespace cdpowder::app
