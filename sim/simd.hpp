#pragma once
// Vector instructions beyond the build's target. On x86-64 (GCC, Clang) the hot loops (the
// pair loop, pair_forces.hpp; the overdamped position updates, position_update.hpp) also have
// a form compiled for AVX2 with __attribute__((target("avx2"))), whatever the build's target,
// and chosen at run time where the processor has it. Every such form gives its scalar form's
// bits: the same IEEE operations in the same order, and no FMA (the build has
// -ffp-contract=off, and no form asks for the FMA instruction set).
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#define JAM_AVX2_FORMS 1
#include <immintrin.h>
#endif

namespace jam {

#if defined(JAM_AVX2_FORMS)
/// Whether this processor (and the operating system) supports AVX2; asked once.
inline bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

}  // namespace jam
