// rng.cpp — the pcg32 engine behind Rng (rng.hpp), kept here so its header stays private.
#include "cdpowder/core/rng.hpp"

#include <pcg_random.hpp>

#include <cstring>
#include <sstream>
#include <type_traits>
#include <utility>

namespace cdpowder {

namespace {

static_assert(sizeof(pcg32) == sizeof(std::array<std::uint64_t, 2>) &&
                  std::is_trivially_copyable_v<pcg32>,
              "Rng holds pcg32's bytes");

pcg32 engine_of(const std::array<std::uint64_t, 2>& bytes) {
  pcg32 engine;
  // (through void*: pcg32 is trivially copyable, asserted above, but not trivial to make)
  std::memcpy(static_cast<void*>(&engine), bytes.data(), sizeof engine);
  return engine;
}

void store(const pcg32& engine, std::array<std::uint64_t, 2>& bytes) {
  std::memcpy(bytes.data(), &engine, sizeof engine);
}

}  // namespace

Rng::Rng() {
  store(pcg32{}, engine_);
}

Rng::Rng(std::uint64_t seed, std::uint64_t stream) {
  store(pcg32{seed, stream}, engine_);
}

std::uint32_t Rng::operator()() {
  pcg32 engine = engine_of(engine_);
  const std::uint32_t bits = engine();
  store(engine, engine_);
  return bits;
}

std::uint32_t Rng::operator()(std::uint32_t bound) {
  pcg32 engine = engine_of(engine_);
  const std::uint32_t draw = engine(bound);
  store(engine, engine_);
  return draw;
}

std::string Rng::text() const {
  std::ostringstream text;
  text << engine_of(engine_);
  return text.str();
}

std::optional<Rng> Rng::from_text(std::string_view text) {
  std::istringstream in{std::string(text)};
  pcg32 engine;
  in >> engine;
  if (in.fail()) return std::nullopt;
  Rng rng;
  store(engine, rng.engine_);
  return rng;
}

double uniform01(Rng& rng) {
  const std::uint64_t hi = rng();
  const std::uint64_t lo = rng();
  const std::uint64_t bits = ((hi << 32U) | lo) >> 11U;
  return static_cast<double>(bits) * 0x1.0p-53;
}

void shuffle_indices(std::span<std::uint32_t> order, Rng& rng) {
  // one engine for the whole shuffle: the same draws as rng(i) one by one
  pcg32 engine = engine_of(rng.engine_);
  for (std::size_t i = order.size(); i > 1; --i) {
    const std::uint32_t j = engine(static_cast<std::uint32_t>(i));
    std::swap(order[i - 1], order[j]);
  }
  store(engine, rng.engine_);
}

}  // namespace cdpowder
