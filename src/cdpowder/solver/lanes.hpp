// lanes.hpp — SIMD lanes for the solver's hot loops over spheres and contacts, once per
// instruction set: SSE2 (2 doubles per register, the x86-64 baseline) and AVX2 (4 doubles,
// chosen at run time where the CPU has it, use_avx2()). A file that vectorises a loop
// includes its lane code once in each namespace, so both see the same source.
// Neither set uses fused multiply-add (no "fma" target, and -ffp-contract=off), and every
// loop built on these gives the same bits on either: the results do not depend on the
// machine.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#define CDP_INLINE [[gnu::always_inline]] inline

namespace cdpowder::lanes {

/// Whether the AVX2 loops run: the CPU has AVX2, and neither CDPOWDER_KERNEL_ISA=sse2 in the
/// environment nor allow_avx2(false) keeps them on SSE2 (to compare the two).
bool use_avx2();

/// Lets the loops use AVX2 where the CPU has it (default), or keeps them on SSE2; returns
/// use_avx2().
bool allow_avx2(bool allowed);

// A record is a 64-byte line of 8 doubles (a SphereVelocity, a ContactAction); load_rows and
// store_rows move fields [kFirst, kFirst + kCount) of kLanes records to and from kCount
// registers, lane l holding record l.

namespace sse2 {
using P = double __attribute__((vector_size(16)));
using M = std::int64_t __attribute__((vector_size(16)));
constexpr int kLanes = 2;

#include "cdpowder/solver/lane_ops.inc"

CDP_INLINE P vsqrt(P x) {
#if defined(__SSE2__)
  return reinterpret_cast<P>(_mm_sqrt_pd(reinterpret_cast<__m128d>(x)));
#else
  return P{std::sqrt(x[0]), std::sqrt(x[1])};
#endif
}

/// every lane of a comparison true
CDP_INLINE bool all_lanes(M mask) {
  return mask[0] != 0 && mask[1] != 0;
}

/// lane l of field f = rows[l][kFirst + f] for f < kCount: fields of two 64-byte records side by
/// side, read two at a time (kFirst, kCount even; the records 16-byte aligned).
template <int kFirst, int kCount>
CDP_INLINE std::array<P, kCount> load_rows(const double* const* rows) {
  std::array<P, kCount> out{};
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  for (int f = 0; f < kCount; f += 2) {
#if defined(__SSE2__)
    const __m128d r0 = _mm_load_pd(rows[0] + kFirst + f);
    const __m128d r1 = _mm_load_pd(rows[1] + kFirst + f);
    out[f] = reinterpret_cast<P>(_mm_unpacklo_pd(r0, r1));
    out[f + 1] = reinterpret_cast<P>(_mm_unpackhi_pd(r0, r1));
#else
    out[f] = P{rows[0][kFirst + f], rows[1][kFirst + f]};
    out[f + 1] = P{rows[0][kFirst + f + 1], rows[1][kFirst + f + 1]};
#endif
  }
  return out;
}

/// rows[l][kFirst + f] = in[f] lane l for f < kCount (load_rows reversed)
template <int kFirst, int kCount>
CDP_INLINE void store_rows(double* const* rows, const std::array<P, kCount>& in) {
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  for (int f = 0; f < kCount; f += 2) {
#if defined(__SSE2__)
    const auto f0 = reinterpret_cast<__m128d>(in[f]);
    const auto f1 = reinterpret_cast<__m128d>(in[f + 1]);
    _mm_store_pd(rows[0] + kFirst + f, _mm_unpacklo_pd(f0, f1));
    _mm_store_pd(rows[1] + kFirst + f, _mm_unpackhi_pd(f0, f1));
#else
    for (int l = 0; l < kLanes; ++l) {
      rows[l][kFirst + f] = in[f][l];
      rows[l][kFirst + f + 1] = in[f + 1][l];
    }
#endif
  }
}
}  // namespace sse2

// (GCC only: the lane code is compiled for AVX2 by `#pragma GCC target`, which clang
// does not know; a clang build, such as the fuzz preset's, runs the SSE2 lanes.)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CDP_HAVE_AVX2 1
#pragma GCC push_options
#pragma GCC target("avx2")

namespace avx2 {
using P = double __attribute__((vector_size(32)));
using M = std::int64_t __attribute__((vector_size(32)));
constexpr int kLanes = 4;

#include "cdpowder/solver/lane_ops.inc"

CDP_INLINE P vsqrt(P x) {
  return reinterpret_cast<P>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(x)));
}

/// every lane of a comparison true
CDP_INLINE bool all_lanes(M mask) {
  return _mm256_movemask_pd(reinterpret_cast<__m256d>(mask)) == 0xF;
}

/// lane l of field f = rows[l][kFirst + f] for f < kCount: fields of four 64-byte records side
/// by side, two at a time: records 0 and 2 in one register, 1 and 3 in another, interleaved
/// (kFirst, kCount even; the records 16-byte aligned).
template <int kFirst, int kCount>
CDP_INLINE std::array<P, kCount> load_rows(const double* const* rows) {
  std::array<P, kCount> out{};
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  for (int f = 0; f < kCount; f += 2) {
    const __m256d r02 =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(rows[0] + kFirst + f)),
                             _mm_load_pd(rows[2] + kFirst + f), 1);
    const __m256d r13 =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(rows[1] + kFirst + f)),
                             _mm_load_pd(rows[3] + kFirst + f), 1);
    out[f] = reinterpret_cast<P>(_mm256_unpacklo_pd(r02, r13));
    out[f + 1] = reinterpret_cast<P>(_mm256_unpackhi_pd(r02, r13));
  }
  return out;
}

/// rows[l][kFirst + f] = in[f] lane l for f < kCount (load_rows reversed)
template <int kFirst, int kCount>
CDP_INLINE void store_rows(double* const* rows, const std::array<P, kCount>& in) {
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  for (int f = 0; f < kCount; f += 2) {
    const auto f0 = reinterpret_cast<__m256d>(in[f]);
    const auto f1 = reinterpret_cast<__m256d>(in[f + 1]);
    const __m256d r02 = _mm256_unpacklo_pd(f0, f1);
    const __m256d r13 = _mm256_unpackhi_pd(f0, f1);
    _mm_store_pd(rows[0] + kFirst + f, _mm256_castpd256_pd128(r02));
    _mm_store_pd(rows[2] + kFirst + f, _mm256_extractf128_pd(r02, 1));
    _mm_store_pd(rows[1] + kFirst + f, _mm256_castpd256_pd128(r13));
    _mm_store_pd(rows[3] + kFirst + f, _mm256_extractf128_pd(r13, 1));
  }
}
}  // namespace avx2

#pragma GCC pop_options
#endif

}  // namespace cdpowder::lanes

/// The lane code `name` (a function, or an instance of a function template, compiled once per
/// set by lanes_instantiate.inc) for this CPU: avx2::name where lanes::use_avx2(), else
/// sse2::name. Both have one type, so the choice is a function pointer.
#if defined(CDP_HAVE_AVX2)
#define CDP_LANES_FOR_CPU(name) (::cdpowder::lanes::use_avx2() ? avx2::name : sse2::name)
#else
#define CDP_LANES_FOR_CPU(name) (sse2::name)
#endif
