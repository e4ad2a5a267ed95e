// run_phase.cpp — the phase in a string kept with its memory reserved ahead, so that naming it
// after an allocation failed allocates as little as possible.
#include "run_phase.hpp"

#include <fmt/format.h>

#include <fstream>
#include <string_view>

namespace cdpowder::app {

namespace {

std::string& phase() {
  static std::string text = [] {
    std::string t;
    t.reserve(256);
    t = "starting";
    return t;
  }();
  return text;
}

std::size_t g_spheres = 0;

/// The process's peak resident memory [GB], or a negative number when it cannot be read.
double peak_gigabytes() {
  try {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.starts_with("VmHWM:")) return std::stod(line.substr(6)) / (1024.0 * 1024.0);
    }
  } catch (...) {  // NOLINT(bugprone-empty-catch): no peak to report then
  }
  return -1.0;
}

}  // namespace

void set_run_phase(std::string_view what, std::size_t spheres) {
  phase().assign(what);
  if (spheres > 0) g_spheres = spheres;
}

std::string out_of_memory_message() {
  const double peak = peak_gigabytes();
  std::string spheres = g_spheres > 0 ? fmt::format(", {} spheres", g_spheres) : "";
  std::string held = peak >= 0.0 ? fmt::format(", about {:.2g} GB held at the peak", peak) : "";
  return fmt::format(
      "out of memory while {}{}{}; a checkpoint written before is kept (free "
      "memory, or run on a machine with more, and resume)",
      phase(), spheres, held);
}

}  // namespace cdpowder::app
