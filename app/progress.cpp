// progress.cpp — formatting the progress line.
#include "progress.hpp"

#include "cdpowder/run/run_messages.hpp"

#include <algorithm>
#include <cstdio>
// isatty, fileno and ioctl(TIOCGWINSZ) are POSIX
#include <sys/ioctl.h>
#include <unistd.h>

namespace cdpowder::app {

namespace {

/// Columns of the terminal on stderr, or 0 when stderr is not a terminal (a log file, a
/// pipe): there a redrawn line would pile carriage returns into the file.
int terminal_columns() {
  if (isatty(fileno(stderr)) == 0) return 0;
  winsize size{};
  if (ioctl(fileno(stderr), TIOCGWINSZ, &size) != 0 || size.ws_col == 0) return 80;
  return size.ws_col;
}

/// Between two plain lines in a log: often enough to see a run move, rarely enough that a
/// day-long run writes a few thousand lines [s].
constexpr double kLogInterval = 30.0;

}  // namespace

ProgressLine::ProgressLine(bool quiet, double interval_seconds)
    : quiet_(quiet), interval_(interval_seconds), columns_(terminal_columns()) {
  if (columns_ == 0) interval_ = std::max(interval_, kLogInterval);
}

void ProgressLine::update(const World& world, const StepReport& report, double fraction) {
  if (quiet_) return;
  passes_since_draw_ += report.solver.passes;
  ++steps_since_draw_;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_ && fraction < 1.0) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double passes = static_cast<double>(passes_since_draw_) /
                        static_cast<double>(std::max<std::int64_t>(1, steps_since_draw_));
  std::string line = progress_text(world, report.diagnostics.contacts, passes, elapsed, fraction);
  if (columns_ == 0) {  // a log: one plain line per report
    std::fprintf(stderr, "progress: %s\n", line.c_str());
    std::fflush(stderr);
    passes_since_draw_ = 0;
    steps_since_draw_ = 0;
    return;
  }
  // redrawn in place, cut to the terminal's width (a wrapped line cannot be redrawn)
  const auto width = static_cast<std::size_t>(std::max(1, columns_ - 1));
  if (line.size() > width) line.resize(width);
  std::fprintf(stderr, "\r%-*s", static_cast<int>(width), line.c_str());
  std::fflush(stderr);
  drawn_ = true;
  passes_since_draw_ = 0;
  steps_since_draw_ = 0;
}

void ProgressLine::finish() {
  if (drawn_) std::fprintf(stderr, "\n");
  drawn_ = false;
}

}  // namespace cdpowder::app
