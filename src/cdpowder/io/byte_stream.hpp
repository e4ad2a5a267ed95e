// byte_stream.hpp — the one binary encoding of engine state: fixed-width little-endian
// integers, doubles as their IEEE-754 bit patterns (so every bit survives, NaN payloads and
// −0.0 included), strings with a length prefix. The state file (state_file.hpp) and the
// determinism hashes (state_hash.hpp) both write through ByteWriter, so what the hash sees
// is exactly what a checkpoint stores.
#pragma once

#include "cdpowder/core/vec3.hpp"
#include "cdpowder/io/output_sink.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace cdpowder {

/// A state file that cannot be read: truncated, corrupted, another format, not a state file.
class StateFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// FNV-1a, 64 bit: a fixed, documented function of the bytes, the same on every platform
/// and build (std::hash is neither).
inline constexpr std::uint64_t kFnv1a64Basis = 14695981039346656037ULL;

/// The FNV-1a state `hash` carried on over `bytes` (fnv1a64(a + b) is
/// fnv1a64_update(fnv1a64(a), b)).
std::uint64_t fnv1a64_update(std::uint64_t hash, std::string_view bytes);

inline std::uint64_t fnv1a64(std::string_view bytes) {
  return fnv1a64_update(kFnv1a64Basis, bytes);
}

/// Encodes into a string (bytes()), or into a sink as it goes: then the bytes are handed to
/// the sink in chunks of about kOutputChunkBytes, and only checksum() of them is kept.
class ByteWriter {
 public:
  ByteWriter() = default;

  /// A writer into `sink`; call flush() after the last write.
  explicit ByteWriter(OutputSink& sink) : sink_(&sink) {}

  void u8(std::uint8_t value) {
    bytes_.push_back(static_cast<char>(value));
    if (sink_ != nullptr && bytes_.size() >= kOutputChunkBytes) flush();
  }

  void u32(std::uint32_t value);
  void u64(std::uint64_t value);

  void i64(std::int64_t value) { u64(static_cast<std::uint64_t>(value)); }

  void f64(double value);
  void vec3(const Vec3& value);

  void boolean(bool value) { u8(value ? 1 : 0); }

  void string(std::string_view text);
  /// A four-letter section tag: a reader that lost its place says where.
  void tag(std::string_view four_letters);

  /// Everything written, when there is no sink.
  [[nodiscard]] const std::string& bytes() const { return bytes_; }

  /// Bytes written so far.
  [[nodiscard]] std::size_t size() const { return handed_over_ + bytes_.size(); }

  /// fnv1a64 of every byte written so far.
  [[nodiscard]] std::uint64_t checksum() const { return fnv1a64_update(hash_, bytes_); }

  /// Hands what is gathered to the sink (nothing without one).
  void flush();

 private:
  void append(std::string_view text);

  OutputSink* sink_ = nullptr;
  std::string bytes_;
  std::uint64_t hash_ = kFnv1a64Basis;  ///< of the bytes handed over
  std::size_t handed_over_ = 0;
};

/// Reads what a ByteWriter wrote; every read is bounds-checked and throws StateFileError
/// naming `source` and the byte offset.
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::string source)
      : bytes_(bytes), source_(std::move(source)) {}

  std::uint8_t u8();
  std::uint32_t u32();
  std::uint64_t u64();

  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }

  double f64();
  Vec3 vec3();
  bool boolean();
  std::string string();
  void tag(std::string_view four_letters);
  /// A count of items of at least `min_item_bytes` each: rejected before any allocation
  /// when the rest of the file could not hold them (a corrupted count never allocates
  /// gigabytes).
  std::size_t count(std::size_t min_item_bytes);

  [[nodiscard]] std::size_t offset() const { return offset_; }

  [[nodiscard]] bool at_end() const { return offset_ == bytes_.size(); }

  [[nodiscard]] const std::string& source() const { return source_; }

  /// The last section tag read, and the byte it began at ("" before the first).
  [[nodiscard]] const std::string& section() const { return section_; }

  [[nodiscard]] std::size_t section_offset() const { return section_offset_; }

  /// Throws StateFileError "SOURCE: at byte N: what".
  [[noreturn]] void fail(std::string_view what) const;

 private:
  const char* take(std::size_t n);

  std::string_view bytes_;
  std::string source_;
  std::size_t offset_ = 0;
  std::string section_;
  std::size_t section_offset_ = 0;
};

}  // namespace cdpowder
