// lanes.cpp — which instruction set the solver's lane loops run on (lanes.hpp).
#include "cdpowder/solver/lanes.hpp"

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

/// CDPOWDER_KERNEL_ISA=sse2 in the environment keeps the SSE2 loops on an AVX2 machine, and
/// =avx2 the AVX2 kernel on an AVX-512 machine
bool avx2_allowed = [] {
  const char* isa = std::getenv("CDPOWDER_KERNEL_ISA");
  return isa == nullptr || std::string_view(isa) != "sse2";
}();

bool avx512_allowed = [] {
  const char* isa = std::getenv("CDPOWDER_KERNEL_ISA");
  return isa == nullptr || (std::string_view(isa) != "sse2" && std::string_view(isa) != "avx2");
}();

}  // namespace

bool use_avx2() {
  return avx2_allowed && cpu_has_avx2();
}

bool allow_avx2(bool allowed) {
  avx2_allowed = allowed;
  return use_avx2();
}

bool use_avx512() {
  return avx512_allowed && use_avx2() && cpu_has_avx512();
}

bool allow_isa(Isa widest) {
  avx2_allowed = widest != Isa::Sse2;
  avx512_allowed = widest == Isa::Avx512;
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
