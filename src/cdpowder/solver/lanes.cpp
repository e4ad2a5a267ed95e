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

/// CDPOWDER_KERNEL_ISA=sse2 in the environment keeps the SSE2 loops on an AVX2 machine
bool avx2_allowed = [] {
  const char* isa = std::getenv("CDPOWDER_KERNEL_ISA");
  return isa == nullptr || std::string_view(isa) != "sse2";
}();

}  // namespace

bool use_avx2() {
  return avx2_allowed && cpu_has_avx2();
}

bool allow_avx2(bool allowed) {
  avx2_allowed = allowed;
  return use_avx2();
}

}  // namespace cdpowder::lanes
