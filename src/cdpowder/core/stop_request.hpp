// stop_request.hpp — how a caller (the command line's signal handler, a pass, later a
// Python callback) asks the library to stop long work: one function, asked between units of
// work (a deposited sphere, a step), the same for every kind of work.
#pragma once

#include <functional>
#include <stdexcept>

namespace cdpowder {

/// Asked between units of work; true stops the work there. An empty one never stops.
using StopRequest = std::function<bool()>;

/// Thrown by work that has no meaningful half-done result when it is asked to stop (a
/// deposit: half a deposit is not the scene's); the message says where it stopped.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cdpowder
