// colouring.hpp — graph colouring of a step's sphere–sphere contacts for the coloured pass
// kernel (solver.kernel = "coloured", coloured_pass.hpp): no two contacts of one colour
// share a sphere, so a colour's contacts can be solved side by side in any order. Greedy in
// contact storage order, each contact taking the lowest colour free at both its spheres, as
// Box2D v3's constraint graph does; a contact for which none of kMaxColours colours is free
// (a sphere with very many contacts) goes to the overflow set, solved one by one. The
// colouring does not know the SIMD lane width.
// For locality the contacts are coloured in chunks of consecutive contacts (contacts are
// stored sorted by their spheres, so a chunk touches a compact set of spheres), each chunk
// with its own colours: a pass then solves a chunk's colours one after the other while the
// chunk's spheres stay in cache, instead of streaming through all spheres once per colour.
// The contacts may come in parts (the tiles of tiles.hpp and their hub), each part coloured on
// its own, so that the parts' colours never mix and the tiles of a phase can be solved on
// threads at once.
#pragma once

#include "cdpowder/contact/local_problem.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace cdpowder {

/// Colours at most (per chunk); the per-sphere masks are one 64-bit word. Box2D v3 uses 24.
inline constexpr int kMaxColours = 24;
/// Contacts per chunk: ≈ 600 spheres' velocities (40 kB) stay in L1/L2 across its colours.
inline constexpr std::size_t kColourChunk = 2048;

struct PairColouring {
  std::vector<ContactIndex> members;         ///< pair indices grouped by colour, storage order
  std::vector<std::uint32_t> colour_start;   ///< colour c is members[start[c], start[c + 1])
  std::vector<std::uint32_t> chunk_colours;  ///< chunk j has colours [cc[j], cc[j + 1])
  std::vector<ContactIndex> overflow;        ///< pairs left without a colour, storage order
  /// part p has chunks [part_chunks[p], part_chunks[p + 1]) and overflow pairs
  /// overflow[part_overflow[p], part_overflow[p + 1]); without parts everything is part 0
  std::vector<std::uint32_t> part_chunks{0, 0};
  std::vector<std::uint32_t> part_overflow{0, 0};
  std::vector<std::uint8_t> colour_of;  ///< scratch: each pair's colour

  [[nodiscard]] std::size_t colours() const {
    return colour_start.empty() ? 0 : colour_start.size() - 1;
  }

  /// Parts of the colouring (one without parts).
  [[nodiscard]] std::size_t parts() const { return part_chunks.size() - 1; }

  [[nodiscard]] std::size_t chunks() const {
    return chunk_colours.empty() ? 0 : chunk_colours.size() - 1;
  }

  /// Part p's colours are [first_colour(p), first_colour(p + 1)) (parts are coloured one
  /// after the other), its batched pairs members[first_member(p), first_member(p + 1)).
  [[nodiscard]] std::uint32_t first_colour(std::size_t part) const {
    return chunk_colours[part_chunks[part]];
  }

  [[nodiscard]] std::uint32_t first_member(std::size_t part) const {
    return colour_start[first_colour(part)];
  }
};

/// Colours `pairs` (bodies < sphere_count) chunk by chunk (`chunk` consecutive contacts, 0 =
/// one chunk) with at most `max_colours` ≤ 64 colours per chunk, all in part 0. `masks` is
/// scratch (one word per sphere), kept by the caller to avoid allocation.
void colour_pairs(const std::vector<PairProblem>& pairs, std::size_t sphere_count, int max_colours,
                  std::size_t chunk, PairColouring& out, std::vector<std::uint64_t>& masks);

/// Colours the pairs part by part: part p < part_start.size() − 1 is the pair indices
/// order[part_start[p], part_start[p + 1]), coloured in that order as colour_pairs colours
/// all pairs. With one part holding 0 … n − 1 it is colour_pairs.
void colour_parts(const std::vector<PairProblem>& pairs, std::span<const ContactIndex> order,
                  std::span<const std::uint32_t> part_start, std::size_t sphere_count,
                  int max_colours, std::size_t chunk, PairColouring& out,
                  std::vector<std::uint64_t>& masks);

/// One chunk, one contact per colour, in storage order: the coloured pass in VisitOrder::Fixed
/// then visits exactly what the scalar pass visits (for tests).
void colour_one_per_colour(std::size_t pair_count, PairColouring& out);

}  // namespace cdpowder
