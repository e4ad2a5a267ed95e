// lanes.cpp — which instruction set the lane loops run on (lanes.hpp).
#include "cdpowder/core/lanes.hpp"

#include <cstdlib>
#include <string_view>

namespace cdpowder::lanes {

namespace {

bool cpu_has_avx2() {
#if defined(CDP_HAVE_AVX2)
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

bool cpu_has_avx512() {
#if defined(CDP_HAVE_AVX512)
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512vl");
  return has;
#else
  return false;
#endif
}

/// The widest set the loops may use: CDPOWDER_KERNEL_ISA=sse2 (or avx2) in the environment
/// keeps the loops on SSE2 (or the coloured kernel on AVX2) on a machine with wider vectors.
Isa widest_allowed = []() noexcept {
  const char* isa = std::getenv("CDPOWDER_KERNEL_ISA");
  if (isa == nullptr) return Isa::Avx512;
  if (std::string_view(isa) == "sse2") return Isa::Sse2;
  if (std::string_view(isa) == "avx2") return Isa::Avx2;
  return Isa::Avx512;
}();

}  // namespace

bool use_avx2() {
  return widest_allowed >= Isa::Avx2 && cpu_has_avx2();
}

bool use_avx512() {
  return widest_allowed == Isa::Avx512 && use_avx2() && cpu_has_avx512();
}

const char* kernel_isa_name() {
  if (use_avx512()) return "avx512";
  return use_avx2() ? "avx2" : "sse2";
}

bool allow_isa(Isa widest) {
  widest_allowed = widest;
  switch (widest) {
    case Isa::Sse2:
      return true;
    case Isa::Avx2:
      return use_avx2();
    case Isa::Avx512:
      return use_avx512();
  }
  return false;
}

}  // namespace cdpowder::lanes
