#pragma once
// The first pass of measure() (observables.hpp) over a block of listed pairs: each pair's
// separation r_i - r_j, f/r (with the force loop's operations, pair_forces.hpp) and energy
// U(r) from r^2, so that the contacts, energy and stress summed from them afterwards, pair by
// pair in the list's order, keep the bits of the one-pair-at-a-time form. Forms:
//  - measure_pairs_scalar: one pair at a time (the reference);
//  - measure_pairs_avx2: four pairs per instruction (the square roots and the division of
//    f/r and U, which the scalar measure computed one contact at a time between the
//    branches of its contact test, run side by side).
// measure_pairs picks the widest form the processor has at run time.
#include <algorithm>
#include <array>
#include <cstdint>

#include "sim/dynamics/pair_forces.hpp"
#include "sim/model/particles.hpp"
#include "sim/simd.hpp"

namespace jam {

/// Pairs per block (their separations stay in the L1 cache until they are summed).
inline constexpr std::uint32_t kMeasureBlockPairs = 256;

template <int D>
struct MeasureBlock {
  alignas(32) std::array<std::array<double, kMeasureBlockPairs>, D> dr;
  alignas(32) std::array<double, kMeasureBlockPairs> force_over_r, energy;
};

/// Pairs [first, k1) of the block starting at k0 (k1 - k0 <= kMeasureBlockPairs) one at a
/// time; first = k0 unless given.
template <int D, class Contact>
void measure_pairs_scalar(const PairLoopInput<D, Contact>& in, std::uint32_t k0, std::uint32_t k1,
                          MeasureBlock<D>& b, std::uint32_t first = 0) {
  for (std::uint32_t k = std::max(k0, first); k < k1; ++k) {
    const std::uint32_t i = in.row_of_pair[k], j = in.neighbors[k];
    double r2 = 0.0;
    for (int d = 0; d < D; ++d) {
      const double dr = in.box_length * minimum_image(in.s[d][i] - in.s[d][j]);
      b.dr[d][k - k0] = dr;
      r2 += dr * dr;
    }
    const int pair = in.type[i] + in.type[j];
    b.force_over_r[k - k0] = in.contact.force_over_r(r2, pair);
    b.energy[k - k0] = in.contact.energy(r2, pair);
  }
}

#if defined(JAM_AVX2_FORMS)
/// Four pairs per AVX2 instruction (no FMA): measure_pairs_scalar's bits.
template <int D, class Contact>
__attribute__((target("avx2"))) void measure_pairs_avx2(const PairLoopInput<D, Contact>& in,
                                                        std::uint32_t k0, std::uint32_t k1,
                                                        MeasureBlock<D>& b) {
  const __m256d length = _mm256_set1_pd(in.box_length);
  std::uint32_t k = k0;
  for (; k + 3 < k1; k += 4) {
    const std::uint32_t* i = in.row_of_pair + k;
    const std::uint32_t* j = in.neighbors + k;
    __m256d r2 = _mm256_setzero_pd();
    for (int d = 0; d < D; ++d) {
      const double* s = in.s[d];
      const __m256d ds = _mm256_sub_pd(_mm256_set_pd(s[i[3]], s[i[2]], s[i[1]], s[i[0]]),
                                       _mm256_set_pd(s[j[3]], s[j[2]], s[j[1]], s[j[0]]));
      const __m256d v = _mm256_mul_pd(length, minimum_image(ds));
      _mm256_store_pd(&b.dr[d][k - k0], v);
      r2 = _mm256_add_pd(r2, _mm256_mul_pd(v, v));
    }
    const std::array<int, 4> pair{in.type[i[0]] + in.type[j[0]], in.type[i[1]] + in.type[j[1]],
                                  in.type[i[2]] + in.type[j[2]], in.type[i[3]] + in.type[j[3]]};
    const __m256d c = in.contact.force_over_r(r2, pair);
    _mm256_store_pd(&b.force_over_r[k - k0], c);
    _mm256_store_pd(&b.energy[k - k0], in.contact.energy(r2, pair));
  }
  measure_pairs_scalar(in, k0, k1, b, k);  // up to three last pairs
}
#endif

/// The fastest form this processor runs (both give the same bits).
template <int D, class Contact>
void measure_pairs(const PairLoopInput<D, Contact>& in, std::uint32_t k0, std::uint32_t k1,
                   MeasureBlock<D>& b) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    measure_pairs_avx2(in, k0, k1, b);
    return;
  }
#endif
  measure_pairs_scalar(in, k0, k1, b);
}

}  // namespace jam
