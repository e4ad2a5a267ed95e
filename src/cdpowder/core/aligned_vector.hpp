// aligned_vector.hpp — std::vector on whole cache lines, for the long vectors the SIMD loops
// stream through (the mixing's iterates and histories). An AVX load of 4 doubles from a vector
// that is only 16-byte aligned (what malloc gives) splits a cache line every other time.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace cdpowder {

inline constexpr std::size_t kCacheLine = 64;  ///< bytes

template <typename T>
struct CacheLineAllocator {
  using value_type = T;

  CacheLineAllocator() = default;

  template <typename U>
  explicit CacheLineAllocator(const CacheLineAllocator<U>& /*other*/) noexcept {}

  [[nodiscard]] T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{kCacheLine}));
  }

  void deallocate(T* p, std::size_t /*n*/) noexcept {
    ::operator delete (p, std::align_val_t{kCacheLine});
  }

  template <typename U>
  bool operator==(const CacheLineAllocator<U>& /*other*/) const noexcept {
    return true;
  }
};

/// A std::vector whose data start on a cache line.
template <typename T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace cdpowder
