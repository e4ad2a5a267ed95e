// group_by_part.hpp — a counting sort of indices by part, shared by the coloured pass (pairs
// and walls by tile) and the split piston (its contacts by tile).
#pragma once

#include "cdpowder/core/index.hpp"
#include "cdpowder/core/pieces.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdpowder {

/// order ← 0 … n − 1 grouped by part (part_of(i) < parts), each part's in index order (a
/// counting sort); start[p] ← where part p begins in `order`, start[parts] = n. `next` is
/// scratch.
template <typename PartOf>
void group_by_part(std::size_t n, std::size_t parts, const PartOf& part_of,
                   std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& next,
                   std::vector<ContactIndex>& order) {
  start.assign(parts + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++start[part_of(i) + 1];
  for (std::size_t p = 0; p < parts; ++p) start[p + 1] += start[p];
  next.assign(start.begin(), start.end() - 1);
  order.resize(n);
  for (std::size_t i = 0; i < n; ++i) order[next[part_of(i)]++] = static_cast<ContactIndex>(i);
}

/// group_by_part in the pieces of indices_per_piece(n) on `runner` (core/pieces.hpp): each
/// piece counts its indices by part, a place is given to each (part, piece) in that order,
/// and each piece writes its own indices there. The pieces are index ranges in index order,
/// so `order` and `start` are those of the counting sort above, bit for bit. `next` is
/// scratch of pieces × parts entries.
template <typename PartOf>
void group_by_part(PieceRunner* runner, std::size_t n, std::size_t parts, const PartOf& part_of,
                   std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& next,
                   std::vector<ContactIndex>& order) {
  const std::size_t per_piece = indices_per_piece(n);
  const std::size_t pieces = chunks_of(n, per_piece);
  if (runner == nullptr || pieces <= 1) {
    group_by_part(n, parts, part_of, start, next, order);
    return;
  }
  // next[q · parts + p]: piece q's count of part p, then the place of its first index of p
  next.assign(pieces * parts, 0);
  run_pieces(runner, static_cast<std::uint32_t>(pieces), [&](std::uint32_t q) {
    std::uint32_t* const count = next.data() + q * parts;
    const IndexRange range = chunk_range(n, per_piece, q);
    for (std::size_t i = range.first; i < range.last; ++i) ++count[part_of(i)];
  });
  start.assign(parts + 1, 0);
  std::uint32_t place = 0;
  for (std::size_t p = 0; p < parts; ++p) {
    start[p] = place;
    for (std::size_t q = 0; q < pieces; ++q) {
      const std::uint32_t count = next[q * parts + p];
      next[q * parts + p] = place;
      place += count;
    }
  }
  start[parts] = place;
  order.resize(n);
  run_pieces(runner, static_cast<std::uint32_t>(pieces), [&](std::uint32_t q) {
    std::uint32_t* const cursor = next.data() + q * parts;
    const IndexRange range = chunk_range(n, per_piece, q);
    for (std::size_t i = range.first; i < range.last; ++i) {
      order[cursor[part_of(i)]++] = static_cast<ContactIndex>(i);
    }
  });
}

}  // namespace cdpowder
