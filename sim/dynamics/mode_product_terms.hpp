#pragma once
// The per-contact terms of y = A x, A = W^-1/2 H_n W^-1/2 (stiffest_mode_estimate.hpp), for a
// block of contacts: with g = sqrt(k) n and a = W^-1/2 of each partner,
//   p       = sum_d g_d (a_i x_i,d - a_j x_j,d),
//   to_i,d  = (a_i p) g_d   (added to y_i),
//   to_j,d  = (a_j p) g_d   (taken from y_j).
// Every contact's terms are independent of the others', so they are computed first, four
// contacts per AVX2 instruction, and only the sums into y (which depend on one another
// through shared particles) stay one contact at a time: the same operations in the same order
// as the one-pass form, so the same bits. Forms:
//  - mode_terms_scalar: one contact at a time (the reference);
//  - mode_terms_avx2: four contacts per instruction (no FMA).
// mode_terms picks the widest form the processor has at run time.
#include <algorithm>
#include <array>
#include <cstdint>

#include "sim/simd.hpp"

namespace jam {

/// Contacts per block (their terms stay in the L1 cache until they are summed into y).
inline constexpr std::uint32_t kModeBlockContacts = 256;

/// The gathered contacts (one entry per contact) and the vector x the product is taken of.
template <int D>
struct ModeProductInput {
  const std::uint32_t* ci;
  const std::uint32_t* cj;
  const double* ai;
  const double* aj;
  std::array<const double*, D> g;
  std::array<const double*, D> x;
};

template <int D>
struct ModeTermsBlock {
  alignas(32) std::array<std::array<double, kModeBlockContacts>, D> to_i, to_j;
};

/// Contacts [first, c1) of the block starting at c0 (c1 - c0 <= kModeBlockContacts) one at a
/// time; first = c0 unless given.
template <int D>
void mode_terms_scalar(const ModeProductInput<D>& in, std::uint32_t c0, std::uint32_t c1,
                       ModeTermsBlock<D>& b, std::uint32_t first = 0) {
  for (std::uint32_t c = std::max(c0, first); c < c1; ++c) {
    const std::uint32_t i = in.ci[c], j = in.cj[c];
    double p = 0.0;
    for (int d = 0; d < D; ++d) p += in.g[d][c] * (in.ai[c] * in.x[d][i] - in.aj[c] * in.x[d][j]);
    for (int d = 0; d < D; ++d) {
      b.to_i[d][c - c0] = in.ai[c] * p * in.g[d][c];
      b.to_j[d][c - c0] = in.aj[c] * p * in.g[d][c];
    }
  }
}

#if defined(JAM_AVX2_FORMS)
/// Four contacts per AVX2 instruction (no FMA): mode_terms_scalar's bits.
template <int D>
__attribute__((target("avx2"))) void mode_terms_avx2(const ModeProductInput<D>& in,
                                                     std::uint32_t c0, std::uint32_t c1,
                                                     ModeTermsBlock<D>& b) {
  std::uint32_t c = c0;
  for (; c + 3 < c1; c += 4) {
    const std::uint32_t* i = in.ci + c;
    const std::uint32_t* j = in.cj + c;
    const __m256d ai = _mm256_loadu_pd(in.ai + c);
    const __m256d aj = _mm256_loadu_pd(in.aj + c);
    __m256d g[D];
    __m256d p = _mm256_setzero_pd();
    for (int d = 0; d < D; ++d) {
      const double* x = in.x[d];
      g[d] = _mm256_loadu_pd(in.g[d] + c);
      const __m256d xi = _mm256_set_pd(x[i[3]], x[i[2]], x[i[1]], x[i[0]]);
      const __m256d xj = _mm256_set_pd(x[j[3]], x[j[2]], x[j[1]], x[j[0]]);
      p = _mm256_add_pd(
          p, _mm256_mul_pd(g[d], _mm256_sub_pd(_mm256_mul_pd(ai, xi), _mm256_mul_pd(aj, xj))));
    }
    const __m256d ai_p = _mm256_mul_pd(ai, p), aj_p = _mm256_mul_pd(aj, p);
    for (int d = 0; d < D; ++d) {
      _mm256_store_pd(&b.to_i[d][c - c0], _mm256_mul_pd(ai_p, g[d]));
      _mm256_store_pd(&b.to_j[d][c - c0], _mm256_mul_pd(aj_p, g[d]));
    }
  }
  mode_terms_scalar(in, c0, c1, b, c);  // up to three last contacts
}
#endif

/// The fastest form this processor runs (both give the same bits).
template <int D>
void mode_terms(const ModeProductInput<D>& in, std::uint32_t c0, std::uint32_t c1,
                ModeTermsBlock<D>& b) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    mode_terms_avx2(in, c0, c1, b);
    return;
  }
#endif
  mode_terms_scalar(in, c0, c1, b);
}

}  // namespace jam
