// rng.hpp — reproducible random streams (pcg32) and the Fisher–Yates shuffle.
// One stream per purpose (deposition, sweep order), so adding draws to one never
// shifts the other. std::shuffle and std::uniform_*_distribution are avoided: their
// sequences differ between standard libraries, ours must not.
#pragma once

#include <pcg_random.hpp>

#include <cstdint>
#include <span>
#include <utility>

namespace cdpowder {

using Rng = pcg32;

/// Stream ids: pcg32's second seed selects an independent sequence.
enum class RngStream : std::uint64_t { SweepOrder = 1, Deposition = 2 };

inline Rng make_rng(std::uint64_t seed, RngStream stream) {
  return {seed, static_cast<std::uint64_t>(stream)};
}

/// Uniform double in [0, 1) with 53 random bits, identical on every platform.
inline double uniform01(Rng& rng) {
  const std::uint64_t hi = rng();
  const std::uint64_t lo = rng();
  const std::uint64_t bits = ((hi << 32U) | lo) >> 11U;
  return static_cast<double>(bits) * 0x1.0p-53;
}

/// Fisher–Yates with pcg32's unbiased bounded draw: the same permutation for a given
/// seed with every compiler and standard library.
template <typename T>
void shuffle_indices(std::span<T> order, Rng& rng) {
  for (std::size_t i = order.size(); i > 1; --i) {
    const auto j = rng(static_cast<std::uint32_t>(i));
    std::swap(order[i - 1], order[j]);
  }
}

}  // namespace cdpowder
