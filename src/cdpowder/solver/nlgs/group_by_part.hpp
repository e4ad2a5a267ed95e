// group_by_part.hpp — a counting sort of indices by part, shared by the coloured pass (pairs
// and walls by tile) and the split piston (its contacts by tile).
#pragma once

#include "cdpowder/core/index.hpp"

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

}  // namespace cdpowder
