// run_phase.hpp — what the command is doing, for the message of a failure that strikes
// anywhere, such as running out of memory: "out of memory while depositing 1000000 spheres".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace cdpowder::app {

/// Records what the command does from now on ("reading the scene", "stepping", …) and, once
/// known, how many spheres it works on (0: not known yet).
void set_run_phase(std::string_view what, std::size_t spheres = 0);

/// The message for std::bad_alloc: the phase, the spheres, and the process's peak memory
/// (VmHWM of /proc/self/status) when it can still be read.
std::string out_of_memory_message();

}  // namespace cdpowder::app
