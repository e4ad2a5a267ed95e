// state_hash.hpp — a 64-bit fingerprint of the physical state: the same bytes a state file
// stores for the World and the warm-start cache (positions, velocities, spheres' constants,
// walls, piston, cell, time, step; every contact action in key order), hashed with FNV-1a.
// Two runs agree to the last bit exactly when their hashes agree (up to a 2⁻⁶⁴ accident).
// The regression tests compare it with golden values (tests/regression/), so a change that
// moves any result by one ulp is seen at once.
#pragma once

#include "cdpowder/model/world.hpp"
#include "cdpowder/solver/step.hpp"

#include <cstdint>
#include <string>

namespace cdpowder {

/// The World and the last committed step's actions (last_step_actions), as a state file
/// stores them.
std::uint64_t state_hash(const World& world, const StepWorkspace& work);

/// "0x" and 16 lower-case hex digits.
std::string hash_text(std::uint64_t hash);

}  // namespace cdpowder
