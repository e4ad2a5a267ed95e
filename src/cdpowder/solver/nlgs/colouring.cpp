// colouring.cpp — greedy colouring of the contact graph (colouring.hpp).
#include "cdpowder/solver/nlgs/colouring.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <numeric>

namespace cdpowder {

namespace {

/// Colours the pairs order[first, last) chunk by chunk, appending colours, chunks and
/// overflow pairs to `out`; masks are all zero before and after.
void colour_range(const std::vector<PairProblem>& pairs, std::span<const ContactIndex> order,
                  std::size_t first_of_part, std::size_t last_of_part, std::uint64_t allowed,
                  std::size_t chunk, PairColouring& out, std::vector<std::uint64_t>& masks) {
  constexpr std::uint8_t kOverflow = 0xff;
  std::vector<std::uint8_t>& colour = out.colour_of;  // by position in `order`
  if (chunk == 0) chunk = std::max<std::size_t>(last_of_part - first_of_part, 1);
  for (std::size_t first = first_of_part; first < last_of_part; first += chunk) {
    const std::size_t last = std::min(last_of_part, first + chunk);
    std::array<std::uint32_t, 64> counts{};
    for (std::size_t i = first; i < last; ++i) {
      const PairProblem& p = pairs[order[i]];
      const std::uint64_t free = ~(masks[p.a] | masks[p.b]) & allowed;
      if (free == 0) {
        colour[i] = kOverflow;
        out.overflow.push_back(order[i]);
        continue;
      }
      const int c = std::countr_zero(free);
      const std::uint64_t bit = std::uint64_t{1} << c;
      masks[p.a] |= bit;
      masks[p.b] |= bit;
      colour[i] = static_cast<std::uint8_t>(c);
      ++counts[static_cast<std::size_t>(c)];
    }
    // the chunk's colours are 0..c_max (greedy never skips one); appended after the others
    std::size_t used = 0;
    for (std::size_t c = 0; c < counts.size(); ++c) {
      if (counts[c] > 0) used = c + 1;
    }
    std::array<std::uint32_t, 64> next{};
    for (std::size_t c = 0; c < used; ++c) {
      next[c] = out.colour_start.back();
      out.colour_start.push_back(out.colour_start.back() + counts[c]);
    }
    out.chunk_colours.push_back(static_cast<std::uint32_t>(out.colour_start.size() - 1));
    out.members.resize(out.colour_start.back());
    for (std::size_t i = first; i < last; ++i) {
      if (colour[i] != kOverflow) out.members[next[colour[i]]++] = order[i];
      masks[pairs[order[i]].a] = 0;  // the next chunk starts afresh
      masks[pairs[order[i]].b] = 0;
    }
  }
}

}  // namespace

void colour_parts(const std::vector<PairProblem>& pairs, std::span<const ContactIndex> order,
                  std::span<const std::uint32_t> part_start, std::size_t sphere_count,
                  int max_colours, std::size_t chunk, PairColouring& out,
                  std::vector<std::uint64_t>& masks) {
  assert(max_colours > 0 && max_colours <= 64);
  masks.assign(sphere_count, 0);
  const std::uint64_t allowed =
      max_colours == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << max_colours) - 1;
  out.overflow.clear();
  out.members.clear();
  out.colour_start.assign(1, 0);
  out.chunk_colours.assign(1, 0);
  out.colour_of.resize(order.size());
  const std::size_t parts = part_start.size() - 1;
  out.part_chunks.assign(parts + 1, 0);
  out.part_overflow.assign(parts + 1, 0);
  for (std::size_t p = 0; p < parts; ++p) {
    colour_range(pairs, order, part_start[p], part_start[p + 1], allowed, chunk, out, masks);
    out.part_chunks[p + 1] = static_cast<std::uint32_t>(out.chunks());
    out.part_overflow[p + 1] = static_cast<std::uint32_t>(out.overflow.size());
  }
}

void colour_pairs(const std::vector<PairProblem>& pairs, std::size_t sphere_count, int max_colours,
                  std::size_t chunk, PairColouring& out, std::vector<std::uint64_t>& masks) {
  std::vector<ContactIndex> order(pairs.size());
  std::iota(order.begin(), order.end(), ContactIndex{0});
  const auto n = static_cast<std::uint32_t>(pairs.size());
  const std::array<std::uint32_t, 2> one_part{0, n};
  colour_parts(pairs, order, one_part, sphere_count, max_colours, chunk, out, masks);
}

void colour_one_per_colour(std::size_t pair_count, PairColouring& out) {
  out.members.resize(pair_count);
  std::iota(out.members.begin(), out.members.end(), ContactIndex{0});
  out.colour_start.resize(pair_count + 1);
  std::iota(out.colour_start.begin(), out.colour_start.end(), std::uint32_t{0});
  out.chunk_colours = {0, static_cast<std::uint32_t>(pair_count)};
  out.overflow.clear();
  out.part_chunks = {0, 1};
  out.part_overflow = {0, 0};
}

}  // namespace cdpowder
