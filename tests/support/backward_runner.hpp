// backward_runner.hpp — a PieceRunner that runs the pieces one after the other, the last
// first: a stage in pieces that gives the bits of one piece on it does not depend on their
// order (the tests of the stages in pieces).
#pragma once

#include "cdpowder/core/pieces.hpp"

#include <cstdint>

namespace cdpowder {

class BackwardRunner final : public PieceRunner {
 public:
  void run_pieces(std::uint32_t pieces, Task task, const void* context) override {
    for (std::uint32_t p = pieces; p > 0; --p) task(context, p - 1);
  }
};

}  // namespace cdpowder
