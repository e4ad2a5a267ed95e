// index.hpp — plain integer indices that address the engine's contiguous arrays.
// Spheres are only ever appended, never deleted mid-run, so no generation counters.
#pragma once

#include <cstdint>

namespace cdpowder {

using BodyIndex = std::uint32_t;     ///< index of a sphere in Bodies
using ContactIndex = std::uint32_t;  ///< index of a contact in Contacts (pairs first, then walls)

/// Ids of the walls in outputs (contacts.csv): spheres are 0..N-1, walls negative.
inline constexpr std::int64_t kBottomWallId = -1;
inline constexpr std::int64_t kPistonId = -2;

}  // namespace cdpowder
