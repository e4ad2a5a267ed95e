// colouring.cpp — greedy colouring of the contact graph (colouring.hpp).
#include "cdpowder/solver/colouring.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <numeric>

namespace cdpowder {

void colour_pairs(const std::vector<PairProblem>& pairs, std::size_t sphere_count, int max_colours,
                  std::size_t chunk, PairColouring& out, std::vector<std::uint64_t>& masks) {
  assert(max_colours > 0 && max_colours <= 64);
  masks.assign(sphere_count, 0);
  const std::uint64_t allowed =
      max_colours == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << max_colours) - 1;
  constexpr std::uint8_t kOverflow = 0xff;
  if (chunk == 0) chunk = std::max<std::size_t>(pairs.size(), 1);
  out.overflow.clear();
  out.members.clear();
  out.colour_start.assign(1, 0);
  out.chunk_colours.assign(1, 0);
  std::vector<std::uint8_t>& colour = out.colour_of;
  colour.resize(pairs.size());
  for (std::size_t first = 0; first < pairs.size(); first += chunk) {
    const std::size_t last = std::min(pairs.size(), first + chunk);
    std::array<std::uint32_t, 64> counts{};
    for (std::size_t k = first; k < last; ++k) {
      const PairProblem& p = pairs[k];
      const std::uint64_t free = ~(masks[p.a] | masks[p.b]) & allowed;
      if (free == 0) {
        colour[k] = kOverflow;
        out.overflow.push_back(static_cast<ContactIndex>(k));
        continue;
      }
      const int c = std::countr_zero(free);
      const std::uint64_t bit = std::uint64_t{1} << c;
      masks[p.a] |= bit;
      masks[p.b] |= bit;
      colour[k] = static_cast<std::uint8_t>(c);
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
    for (std::size_t k = first; k < last; ++k) {
      if (colour[k] != kOverflow) out.members[next[colour[k]]++] = static_cast<ContactIndex>(k);
      masks[pairs[k].a] = 0;  // the next chunk starts afresh
      masks[pairs[k].b] = 0;
    }
  }
}

void colour_one_per_colour(std::size_t pair_count, PairColouring& out) {
  out.members.resize(pair_count);
  std::iota(out.members.begin(), out.members.end(), ContactIndex{0});
  out.colour_start.resize(pair_count + 1);
  std::iota(out.colour_start.begin(), out.colour_start.end(), std::uint32_t{0});
  out.chunk_colours = {0, static_cast<std::uint32_t>(pair_count)};
  out.overflow.clear();
}

}  // namespace cdpowder
