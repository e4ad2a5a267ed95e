// byte_stream.cpp — little-endian encoding, bounds-checked decoding, FNV-1a.
#include "cdpowder/io/byte_stream.hpp"

#include <fmt/format.h>

#include <bit>

namespace cdpowder {

void ByteWriter::u32(std::uint32_t value) {
  for (int k = 0; k < 4; ++k) u8(static_cast<std::uint8_t>(value >> (8U * k)));
}

void ByteWriter::u64(std::uint64_t value) {
  for (int k = 0; k < 8; ++k) u8(static_cast<std::uint8_t>(value >> (8U * k)));
}

void ByteWriter::f64(double value) {
  u64(std::bit_cast<std::uint64_t>(value));
}

void ByteWriter::vec3(const Vec3& value) {
  f64(value.x());
  f64(value.y());
  f64(value.z());
}

void ByteWriter::string(std::string_view text) {
  u64(text.size());
  append(text);
}

void ByteWriter::tag(std::string_view four_letters) {
  append(four_letters.substr(0, 4));
}

void ByteWriter::append(std::string_view text) {
  bytes_.append(text);
  if (sink_ != nullptr && bytes_.size() >= kOutputChunkBytes) flush();
}

void ByteWriter::flush() {
  if (sink_ == nullptr || bytes_.empty()) return;
  hash_ = fnv1a64_update(hash_, bytes_);
  handed_over_ += bytes_.size();
  sink_->write(bytes_);
  bytes_.clear();
}

const char* ByteReader::take(std::size_t n) {
  if (n > bytes_.size() - offset_) {
    fail(fmt::format("the file ends early (needs {} more bytes, has {}): truncated", n,
                     bytes_.size() - offset_));
  }
  const char* at = bytes_.data() + offset_;
  offset_ += n;
  return at;
}

std::uint8_t ByteReader::u8() {
  return static_cast<std::uint8_t>(*take(1));
}

std::uint32_t ByteReader::u32() {
  const char* at = take(4);
  std::uint32_t value = 0;
  for (int k = 0; k < 4; ++k)
    value |= static_cast<std::uint32_t>(static_cast<unsigned char>(at[k])) << (8U * k);
  return value;
}

std::uint64_t ByteReader::u64() {
  const char* at = take(8);
  std::uint64_t value = 0;
  for (int k = 0; k < 8; ++k)
    value |= static_cast<std::uint64_t>(static_cast<unsigned char>(at[k])) << (8U * k);
  return value;
}

double ByteReader::f64() {
  return std::bit_cast<double>(u64());
}

Vec3 ByteReader::vec3() {
  const double x = f64();
  const double y = f64();
  const double z = f64();
  return {x, y, z};
}

bool ByteReader::boolean() {
  const std::uint8_t value = u8();
  if (value > 1) fail(fmt::format("a flag holds {}, expected 0 or 1", value));
  return value == 1;
}

std::string ByteReader::string() {
  const std::size_t n = count(1);
  return {take(n), n};
}

void ByteReader::tag(std::string_view four_letters) {
  const std::size_t at = offset_;
  const std::string_view found(take(4), 4);
  if (found != four_letters.substr(0, 4)) {
    offset_ = at;
    fail(fmt::format("expected the section '{}', found other bytes: corrupted or another format",
                     four_letters));
  }
  section_ = std::string(four_letters.substr(0, 4));
  section_offset_ = at;
}

std::size_t ByteReader::count(std::size_t min_item_bytes) {
  const std::uint64_t n = u64();
  const std::size_t left = bytes_.size() - offset_;
  if (min_item_bytes > 0 && n > left / min_item_bytes) {
    fail(fmt::format("a count of {} items cannot fit in the {} bytes left: corrupted", n, left));
  }
  return static_cast<std::size_t>(n);
}

void ByteReader::fail(std::string_view what) const {
  throw StateFileError(fmt::format("{}: at byte {}: {}", source_, offset_, what));
}

std::uint64_t fnv1a64_update(std::uint64_t hash, std::string_view bytes) {
  static_assert(kFnv1a64Basis == 0xcbf29ce484222325ULL, "the FNV offset basis");
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;  // FNV prime
  }
  return hash;
}

}  // namespace cdpowder
