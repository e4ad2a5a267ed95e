// lanes.hpp — SIMD lanes for the hot loops over spheres and contacts (the solver's kernels,
// detection's candidate pairs, the step's measurements), once per instruction set: SSE2 (2
// doubles per register, the x86-64 baseline) and AVX2 (4 doubles, chosen at run time where the
// CPU has it, use_avx2()), and for the coloured kernel AVX-512 (8 doubles, use_avx512(); other
// lane code may opt in, lanes_instantiate.inc, where it pays: detection's pair search did not).
// A file that vectorises a loop includes its lane code once in each namespace
// (lanes_instantiate.inc), so all see the same source. No set uses fused multiply-add (no FMA
// intrinsics, and -ffp-contract=off), and every loop built on these gives the same bits on any
// of them: the results do not depend on the machine.
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
/// a lambda's body inlined where it is called: [&](…) CDP_LAMBDA_INLINE { … }
#define CDP_LAMBDA_INLINE __attribute__((always_inline))

namespace cdpowder::lanes {

/// The instruction sets of the lane loops, narrowest first.
enum class Isa : std::uint8_t { Sse2, Avx2, Avx512 };

/// Whether the AVX2 loops run: the CPU has AVX2, and neither CDPOWDER_KERNEL_ISA=sse2 in the
/// environment nor allow_isa(Isa::Sse2) keeps them on SSE2 (to compare the two).
bool use_avx2();

/// Whether the coloured kernel runs on AVX-512: use_avx2(), the CPU has AVX-512 F, DQ and VL,
/// and neither CDPOWDER_KERNEL_ISA=avx2 (or sse2) nor allow_isa keeps it on AVX2.
bool use_avx512();

/// Lets the loops use instruction sets up to `widest` where the CPU has them (the default:
/// Avx512, unless CDPOWDER_KERNEL_ISA says sse2 or avx2); returns whether `widest` is the one
/// the coloured kernel now uses (false where the CPU lacks it). Every set gives the same bits.
bool allow_isa(Isa widest);

/// The instruction set the coloured kernel runs on in this process, as run summaries name it:
/// "avx512", "avx2" or "sse2". Every set gives the same bits; the time differs.
const char* kernel_isa_name();

// A record is a 64-byte line of 8 doubles (a SphereVelocity, a ContactAction); load_rows and
// store_rows move fields [kFirst, kFirst + kCount) of kLanes records to and from kCount
// registers, lane l holding record rows[l] (`rows`: an array of record pointers, or anything
// that gives lane l's record by rows[l]).

namespace sse2 {
using P = double __attribute__((vector_size(16)));
using M = std::int64_t __attribute__((vector_size(16)));
constexpr int kLanes = 2;

#include "cdpowder/core/lane_ops.inc"

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
template <int kFirst, int kCount, typename Rows>
CDP_INLINE std::array<P, kCount> load_rows(const Rows& rows) {
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
template <int kFirst, int kCount, typename Rows>
CDP_INLINE void store_rows(const Rows& rows, const std::array<P, kCount>& in) {
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

#include "cdpowder/core/lane_ops.inc"

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
template <int kFirst, int kCount, typename Rows>
CDP_INLINE std::array<P, kCount> load_rows(const Rows& rows) {
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
template <int kFirst, int kCount, typename Rows>
CDP_INLINE void store_rows(const Rows& rows, const std::array<P, kCount>& in) {
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

// AVX-512 (8 doubles), for the coloured kernel: one register holds two batches of four
// contacts (coloured_kernel.inc), which doubles the independent work in flight. (GCC only, as
// AVX2; compiled with avx512f, dq and vl, run where the CPU has all three: use_avx512().)
#if defined(CDP_HAVE_AVX2)
#define CDP_HAVE_AVX512 1
#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512dq,avx512vl")

namespace avx512 {
using P = double __attribute__((vector_size(64)));
using M = std::int64_t __attribute__((vector_size(64)));
constexpr int kLanes = 8;

#include "cdpowder/core/lane_ops.inc"

CDP_INLINE P vsqrt(P x) {
  return reinterpret_cast<P>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(x)));
}

/// every lane of a comparison true
CDP_INLINE bool all_lanes(M mask) {
  return _mm512_movepi64_mask(reinterpret_cast<__m512i>(mask)) == 0xFF;
}

/// fields f, f + 1 of records r[0], r[2], r[4], r[6] (or r[1], r[3], …) in the 128-bit lanes
/// of one register
CDP_INLINE __m512d four_records(const double* r0, const double* r1, const double* r2,
                                const double* r3) {
  __m512d v = _mm512_castpd128_pd512(_mm_load_pd(r0));
  v = _mm512_insertf64x2(v, _mm_load_pd(r1), 1);
  v = _mm512_insertf64x2(v, _mm_load_pd(r2), 2);
  return _mm512_insertf64x2(v, _mm_load_pd(r3), 3);
}

/// Pairs of lanes of a and b, interleaved: [a0 a1 b0 b1 a4 a5 b4 b5] (kSecond false) or
/// [a2 a3 b2 b3 a6 a7 b6 b7], one step of the 4 × 4 transposes below
template <bool kSecond>
CDP_INLINE __m512d pick_pairs(__m512d a, __m512d b) {
  const __m512i index = kSecond ? _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15)
                                : _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  return _mm512_permutex2var_pd(a, index, b);
}

/// Fields [at, at + 4) of the eight records: a 4 × 4 transpose in each half of four registers
/// that hold records j and j + 4 (twelve shuffles for four fields, against sixteen two fields
/// at a time).
template <typename Rows>
CDP_INLINE void load_four_fields(const Rows& rows, int at, P* out) {
  // r(j): record j's four fields, then record j + 4's
  const auto r = [&](int j) {
    return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(rows[j] + at)),
                              _mm256_loadu_pd(rows[j + 4] + at), 1);
  };
  const __m512d r0 = r(0);
  const __m512d r1 = r(1);
  const __m512d r2 = r(2);
  const __m512d r3 = r(3);
  const __m512d t0 = _mm512_unpacklo_pd(r0, r1);  // fields 0, 2 of records 0, 1, 4, 5
  const __m512d t1 = _mm512_unpackhi_pd(r0, r1);  // fields 1, 3
  const __m512d t2 = _mm512_unpacklo_pd(r2, r3);  // fields 0, 2 of records 2, 3, 6, 7
  const __m512d t3 = _mm512_unpackhi_pd(r2, r3);
  out[0] = reinterpret_cast<P>(pick_pairs<false>(t0, t2));
  out[1] = reinterpret_cast<P>(pick_pairs<false>(t1, t3));
  out[2] = reinterpret_cast<P>(pick_pairs<true>(t0, t2));
  out[3] = reinterpret_cast<P>(pick_pairs<true>(t1, t3));
}

/// load_four_fields reversed
template <typename Rows>
CDP_INLINE void store_four_fields(const Rows& rows, int at, const P* in) {
  const auto f0 = reinterpret_cast<__m512d>(in[0]);
  const auto f1 = reinterpret_cast<__m512d>(in[1]);
  const auto f2 = reinterpret_cast<__m512d>(in[2]);
  const auto f3 = reinterpret_cast<__m512d>(in[3]);
  const __m512d t0 = pick_pairs<false>(f0, f2);  // fields 0, 2 of records 0, 1, 4, 5
  const __m512d t1 = pick_pairs<false>(f1, f3);  // fields 1, 3
  const __m512d t2 = pick_pairs<true>(f0, f2);   // fields 0, 2 of records 2, 3, 6, 7
  const __m512d t3 = pick_pairs<true>(f1, f3);
  // record j's four fields, then record j + 4's
  const auto store_records = [&](int j, __m512d r) {
    _mm256_storeu_pd(rows[j] + at, _mm512_castpd512_pd256(r));
    _mm256_storeu_pd(rows[j + 4] + at, _mm512_extractf64x4_pd(r, 1));
  };
  store_records(0, _mm512_unpacklo_pd(t0, t1));
  store_records(1, _mm512_unpackhi_pd(t0, t1));
  store_records(2, _mm512_unpacklo_pd(t2, t3));
  store_records(3, _mm512_unpackhi_pd(t2, t3));
}

/// lane l of field f = rows[l][kFirst + f] for f < kCount: fields of eight 64-byte records
/// side by side, four at a time, then two (kFirst, kCount even; the records 16-byte aligned).
template <int kFirst, int kCount, typename Rows>
CDP_INLINE std::array<P, kCount> load_rows(const Rows& rows) {
  std::array<P, kCount> out{};
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  int f = 0;
  for (; f + 4 <= kCount; f += 4) load_four_fields(rows, kFirst + f, out.data() + f);
  for (; f < kCount; f += 2) {
    const int at = kFirst + f;
    const __m512d even = four_records(rows[0] + at, rows[2] + at, rows[4] + at, rows[6] + at);
    const __m512d odd = four_records(rows[1] + at, rows[3] + at, rows[5] + at, rows[7] + at);
    out[f] = reinterpret_cast<P>(_mm512_unpacklo_pd(even, odd));
    out[f + 1] = reinterpret_cast<P>(_mm512_unpackhi_pd(even, odd));
  }
  return out;
}

/// rows[l][kFirst + f] = in[f] lane l for f < kCount (load_rows reversed)
template <int kFirst, int kCount, typename Rows>
CDP_INLINE void store_rows(const Rows& rows, const std::array<P, kCount>& in) {
  static_assert(kFirst % 2 == 0 && kCount % 2 == 0);
  int f = 0;
  for (; f + 4 <= kCount; f += 4) store_four_fields(rows, kFirst + f, in.data() + f);
  for (; f < kCount; f += 2) {
    const int at = kFirst + f;
    const auto f0 = reinterpret_cast<__m512d>(in[f]);
    const auto f1 = reinterpret_cast<__m512d>(in[f + 1]);
    const __m512d even = _mm512_unpacklo_pd(f0, f1);  // records 0, 2, 4, 6
    const __m512d odd = _mm512_unpackhi_pd(f0, f1);   // records 1, 3, 5, 7
    _mm_store_pd(rows[0] + at, _mm512_castpd512_pd128(even));
    _mm_store_pd(rows[2] + at, _mm512_extractf64x2_pd(even, 1));
    _mm_store_pd(rows[4] + at, _mm512_extractf64x2_pd(even, 2));
    _mm_store_pd(rows[6] + at, _mm512_extractf64x2_pd(even, 3));
    _mm_store_pd(rows[1] + at, _mm512_castpd512_pd128(odd));
    _mm_store_pd(rows[3] + at, _mm512_extractf64x2_pd(odd, 1));
    _mm_store_pd(rows[5] + at, _mm512_extractf64x2_pd(odd, 2));
    _mm_store_pd(rows[7] + at, _mm512_extractf64x2_pd(odd, 3));
  }
}
}  // namespace avx512

#pragma GCC pop_options
#endif

}  // namespace cdpowder::lanes

/// The lane code `name` (a function, or an instance of a function template, compiled once per
/// set by lanes_instantiate.inc) for this CPU: avx2::name where lanes::use_avx2(), else
/// sse2::name. Both have one type, so the choice is a function pointer. (Variadic, so that a
/// name may carry template arguments: CDP_LANES_FOR_CPU(f<true, false>).)
#if defined(CDP_HAVE_AVX2)
#define CDP_LANES_FOR_CPU(...) \
  (::cdpowder::lanes::use_avx2() ? avx2::__VA_ARGS__ : sse2::__VA_ARGS__)
#else
#define CDP_LANES_FOR_CPU(...) (sse2::__VA_ARGS__)
#endif

/// CDP_LANES_FOR_CPU, with avx512::name where lanes::use_avx512(): for lane code instantiated
/// on AVX-512 as well (CDP_LANE_CODE_AVX512, lanes_instantiate.inc).
#if defined(CDP_HAVE_AVX512)
#define CDP_WIDE_LANES_FOR_CPU(...) \
  (::cdpowder::lanes::use_avx512() ? avx512::__VA_ARGS__ : CDP_LANES_FOR_CPU(__VA_ARGS__))
#else
#define CDP_WIDE_LANES_FOR_CPU(...) CDP_LANES_FOR_CPU(__VA_ARGS__)
#endif
