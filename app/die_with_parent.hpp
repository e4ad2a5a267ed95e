// die_with_parent.hpp — a sweep's runs end when the sweep ends, even when it is killed with
// SIGKILL (measured before: its runs kept running after the sweep's folder lock was gone,
// and a restarted sweep started the same runs again into the same folders). The sweep names
// itself in an environment variable; a run that finds it asks the kernel for SIGTERM at the
// sweep's death, which the run handles as a Ctrl-C: it finishes its step, writes its
// outputs flagged interrupted, and releases its folder.
#pragma once

#include <cstdlib>

// prctl is Linux; getppid, raise and unsetenv are POSIX
#include <signal.h>  // NOLINT(modernize-deprecated-headers)
#include <sys/prctl.h>
#include <unistd.h>

namespace cdpowder::app {

/// Holds the sweep's process id while it runs; read and removed by its runs.
inline constexpr const char* kDieWithParentVariable = "CDPOWDER_DIE_WITH_PARENT";

/// Called first thing in main: in a run started by a sweep, SIGTERM when the sweep dies
/// (at once if it already has).
inline void die_with_parent_if_asked() {
  const char* value = std::getenv(kDieWithParentVariable);
  if (value == nullptr) return;
  const long parent = std::strtol(value, nullptr, 10);
  unsetenv(kDieWithParentVariable);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != static_cast<pid_t>(parent)) raise(SIGTERM);
}

}  // namespace cdpowder::app
