// rng.hpp — reproducible random streams (pcg32) and the Fisher–Yates shuffle.
// One stream per purpose (deposition, pass order), so adding draws to one never
// shifts the other. std::shuffle and std::uniform_*_distribution are avoided: their
// sequences differ between standard libraries, ours must not. The engine is pcg-cpp's
// pcg32, kept inside core/rng.cpp so that no pcg header reaches the library's users.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace cdpowder {

/// A pcg32 stream: 64 bits of state and 64 of stream increment, advanced by core/rng.cpp.
class Rng {
 public:
  /// pcg32's default-seeded stream.
  Rng();
  /// pcg32(seed, stream): `stream` selects one of 2^63 independent sequences.
  Rng(std::uint64_t seed, std::uint64_t stream);

  /// The next 32 random bits.
  std::uint32_t operator()();
  /// Uniform in [0, bound) without bias (pcg32's bounded draw), bound ≥ 1.
  std::uint32_t operator()(std::uint32_t bound);

  /// pcg-cpp's exact text form (multiplier, increment, state), as the state file stores it.
  [[nodiscard]] std::string text() const;
  /// The stream of `text()`'s form; nullopt when the text is not one.
  static std::optional<Rng> from_text(std::string_view text);

  friend bool operator==(const Rng&, const Rng&) = default;
  friend void shuffle_indices(std::span<std::uint32_t> order, Rng& rng);

 private:
  std::array<std::uint64_t, 2> engine_{};  ///< pcg32's bytes (core/rng.cpp)
};

/// Stream ids: pcg32's second seed selects an independent sequence.
enum class RngStream : std::uint64_t { PassOrder = 1, Deposition = 2 };

inline Rng make_rng(std::uint64_t seed, RngStream stream) {
  return {seed, static_cast<std::uint64_t>(stream)};
}

/// Uniform double in [0, 1) with 53 random bits, identical on every platform.
double uniform01(Rng& rng);

/// Fisher–Yates with pcg32's unbiased bounded draw: the same permutation for a given
/// seed with every compiler and standard library.
void shuffle_indices(std::span<std::uint32_t> order, Rng& rng);

}  // namespace cdpowder
