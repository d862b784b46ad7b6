#pragma once
// The pair loop of the elastic forces over rows of the half neighbor list, written once for
// every contact law (a template parameter: sim/model/contact_law.hpp), in forms that give the
// same bits:
//  - write_pair_forces_scalar: one pair at a time (the reference form);
//  - write_pair_forces_sse2 / _avx2: the pair forces of a block of pairs first, two
//    (SSE2) or four (AVX2) pairs per instruction (sqrt and division, the costly part, run side
//    by side), then the forces added pair by pair in the list's order.
// write_pair_forces picks the widest form the processor has at run time.
// Every operation is an IEEE-754 operation on doubles, correctly rounded the same way in a
// packed register as alone, and the additions into the forces happen in the same order, so the
// forms agree bit for bit (tests/test_pair_forces.cpp checks it).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "sim/model/contact_law.hpp"
#include "sim/model/particles.hpp"
#include "sim/simd.hpp"

namespace jam {

/// Where the pair loop adds forces: one array per dimension (std::type_identity_t keeps D
/// deduced from PairLoopInput alone).
template <int D>
using ForceArrays = std::type_identity_t<std::array<double*, D>>;

/// What the pair loop reads: the list (CSR rows and the row of every pair), species, positions,
/// the contact law.
template <int D, class Contact>
struct PairLoopInput {
  const std::uint32_t* offsets;      // row i is pairs [offsets[i], offsets[i+1])
  const std::uint32_t* neighbors;    // j of every pair
  const std::uint32_t* row_of_pair;  // i of every pair
  const std::uint8_t* type;
  std::array<const double*, D> s;  // scaled positions
  Contact contact;                 // f/r of a pair, alone or packed
  double box_length;
};

/// The force f_ij = (f/r) (r_i - r_j) on i from j (the law's f/r at the minimum-image
/// separation): the scalar operations every form reproduces.
template <int D, class Contact>
std::array<double, D> pair_force(const PairLoopInput<D, Contact>& in, std::uint32_t i,
                                 std::uint32_t j) {
  std::array<double, D> dr;
  double r2 = 0.0;
  for (int d = 0; d < D; ++d) {
    dr[d] = in.box_length * minimum_image(in.s[d][i] - in.s[d][j]);
    r2 += dr[d] * dr[d];
  }
  const double c = in.contact.force_over_r(r2, in.type[i] + in.type[j]);
  for (int d = 0; d < D; ++d) dr[d] *= c;
  return dr;
}

/// Adds the forces of the pairs in rows [first, last) into f (both partners), one pair at a
/// time.
template <int D, class Contact>
void accumulate_pair_forces_scalar(const PairLoopInput<D, Contact>& in, std::size_t first,
                                   std::size_t last, const ForceArrays<D>& f) {
  for (std::size_t i = first; i < last; ++i) {
    std::array<double, D> fi{};
    for (std::uint32_t k = in.offsets[i]; k < in.offsets[i + 1]; ++k) {
      const std::uint32_t j = in.neighbors[k];
      const std::array<double, D> f_ij = pair_force(in, static_cast<std::uint32_t>(i), j);
      for (int d = 0; d < D; ++d) {
        fi[d] += f_ij[d];
        f[d][j] -= f_ij[d];
      }
    }
    for (int d = 0; d < D; ++d) f[d][i] += fi[d];
  }
}

/// Pairs of one block: whole rows of at most kBlockPairs pairs (a longer row goes alone, up to
/// kBlockSpare more; rows are far shorter), so that a block's separations stay in the L1 cache
/// between the two passes of the blocked forms.
inline constexpr std::size_t kBlockPairs = 256;
inline constexpr std::size_t kBlockSpare = 64;

/// The first pass's output for a block: the pair forces f_ij = (f/r) (r_i - r_j), by pair
/// k - k0 (the products computed there, packed, as the scalar form computes them).
template <int D>
struct PairBlock {
  alignas(32) std::array<std::array<double, kBlockPairs + kBlockSpare>, D> f_ij;
};

/// First pass for the one pair k of a block starting at k0 (the scalar operations).
template <int D, class Contact>
void separation_and_force_over_r(const PairLoopInput<D, Contact>& in, std::uint32_t k,
                                 std::uint32_t k0, PairBlock<D>& b) {
  const std::array<double, D> f_ij = pair_force(in, in.row_of_pair[k], in.neighbors[k]);
  for (int d = 0; d < D; ++d) b.f_ij[d][k - k0] = f_ij[d];
}

/// The reference for every form: sets f[d][first, n) to the forces of the pairs in rows
/// [first, last) of a system of n particles (zero, then the scalar form). The pairs (i, j) of
/// those rows have first <= i < j < n, so f below first is neither read nor written.
template <int D, class Contact>
void write_pair_forces_scalar(const PairLoopInput<D, Contact>& in, std::size_t first,
                              std::size_t last, std::size_t n, const ForceArrays<D>& f) {
  for (int d = 0; d < D; ++d) std::fill(f[d] + first, f[d] + n, 0.0);
  accumulate_pair_forces_scalar(in, first, last, f);
}

/// The pair loop in blocks, with write_pair_forces_scalar's result bit for bit: FirstPass fills
/// a block's pair forces (vectorized: the sqrt and division are the costly part), then they are
/// added pair by pair in the order of the scalar form.
template <int D, class Contact,
          void (*FirstPass)(const PairLoopInput<D, Contact>&, std::uint32_t, std::uint32_t,
                            PairBlock<D>&)>
void write_pair_forces_in_blocks(const PairLoopInput<D, Contact>& in, std::size_t first,
                                 std::size_t last, std::size_t n, const ForceArrays<D>& f) {
  // Zeroing each entry just before the block that first touches it instead (so that it comes
  // from the cache) measured 0.93x in 2D at N = 262144: one pass it stays.
  for (int d = 0; d < D; ++d) std::fill(f[d] + first, f[d] + n, 0.0);
  PairBlock<D> b;
  std::size_t row = first;
  while (row < last) {
    const std::uint32_t k0 = in.offsets[row];
    std::size_t row_end = row + 1;
    while (row_end < last && in.offsets[row_end + 1] - k0 <= kBlockPairs) ++row_end;
    const std::uint32_t k1 = in.offsets[row_end];
    if (k1 - k0 > kBlockPairs + kBlockSpare) {  // a pathological row: the reference form
      accumulate_pair_forces_scalar(in, row, row_end, f);
      row = row_end;
      continue;
    }
    FirstPass(in, k0, k1, b);
    for (std::size_t i = row; i < row_end; ++i) {
      std::array<double, D> fi{};
      for (std::uint32_t q = in.offsets[i]; q < in.offsets[i + 1]; ++q) {
        const std::uint32_t j = in.neighbors[q];
        for (int d = 0; d < D; ++d) {
          fi[d] += b.f_ij[d][q - k0];
          f[d][j] -= b.f_ij[d][q - k0];
        }
      }
      for (int d = 0; d < D; ++d) f[d][i] += fi[d];
    }
    row = row_end;
  }
}

#if defined(__SSE2__)
/// First pass, two pairs per SSE2 instruction.
template <int D, class Contact>
void separations_and_force_over_r_sse2(const PairLoopInput<D, Contact>& in, std::uint32_t k0,
                                       std::uint32_t k1, PairBlock<D>& b) {
  const __m128d length = _mm_set1_pd(in.box_length);
  std::uint32_t k = k0;
  for (; k + 1 < k1; k += 2) {
    const std::uint32_t* i = in.row_of_pair + k;
    const std::uint32_t* j = in.neighbors + k;
    __m128d v[D];
    __m128d r2 = _mm_setzero_pd();
    for (int d = 0; d < D; ++d) {
      const double* s = in.s[d];
      const __m128d ds = _mm_sub_pd(_mm_set_pd(s[i[1]], s[i[0]]), _mm_set_pd(s[j[1]], s[j[0]]));
      v[d] = _mm_mul_pd(length, minimum_image(ds));
      r2 = _mm_add_pd(r2, _mm_mul_pd(v[d], v[d]));
    }
    const __m128d c = in.contact.force_over_r(
        r2, std::array<int, 2>{in.type[i[0]] + in.type[j[0]], in.type[i[1]] + in.type[j[1]]});
    for (int d = 0; d < D; ++d) _mm_store_pd(&b.f_ij[d][k - k0], _mm_mul_pd(c, v[d]));
  }
  if (k < k1) separation_and_force_over_r(in, k, k0, b);  // an odd last pair
}

/// write_pair_forces_scalar's result, bit for bit, with f/r of two pairs per SSE2 instruction.
template <int D, class Contact>
void write_pair_forces_sse2(const PairLoopInput<D, Contact>& in, std::size_t first,
                            std::size_t last, std::size_t n, const ForceArrays<D>& f) {
  write_pair_forces_in_blocks<D, Contact, separations_and_force_over_r_sse2<D, Contact>>(
      in, first, last, n, f);
}
#endif

#if defined(JAM_AVX2_FORMS)
/// First pass, four pairs per AVX2 instruction (compiled for AVX2 whatever the build's target,
/// called only where the processor has it). No FMA: the same roundings as the scalar form.
template <int D, class Contact>
__attribute__((target("avx2"))) void separations_and_force_over_r_avx2(
    const PairLoopInput<D, Contact>& in, std::uint32_t k0, std::uint32_t k1, PairBlock<D>& b) {
  const __m256d length = _mm256_set1_pd(in.box_length);
  std::uint32_t k = k0;
  for (; k + 3 < k1; k += 4) {
    const std::uint32_t* i = in.row_of_pair + k;
    const std::uint32_t* j = in.neighbors + k;
    __m256d v[D];
    __m256d r2 = _mm256_setzero_pd();
    for (int d = 0; d < D; ++d) {
      const double* s = in.s[d];
      const __m256d ds = _mm256_sub_pd(_mm256_set_pd(s[i[3]], s[i[2]], s[i[1]], s[i[0]]),
                                       _mm256_set_pd(s[j[3]], s[j[2]], s[j[1]], s[j[0]]));
      v[d] = _mm256_mul_pd(length, minimum_image(ds));
      r2 = _mm256_add_pd(r2, _mm256_mul_pd(v[d], v[d]));
    }
    const __m256d c = in.contact.force_over_r(
        r2, std::array<int, 4>{in.type[i[0]] + in.type[j[0]], in.type[i[1]] + in.type[j[1]],
                               in.type[i[2]] + in.type[j[2]], in.type[i[3]] + in.type[j[3]]});
    for (int d = 0; d < D; ++d) _mm256_store_pd(&b.f_ij[d][k - k0], _mm256_mul_pd(c, v[d]));
  }
  for (; k < k1; ++k) separation_and_force_over_r(in, k, k0, b);  // up to three last pairs
}

/// write_pair_forces_scalar's result, bit for bit, with f/r of four pairs per AVX2
/// instruction. Only on a processor with AVX2 (cpu_has_avx2()).
template <int D, class Contact>
void write_pair_forces_avx2(const PairLoopInput<D, Contact>& in, std::size_t first,
                            std::size_t last, std::size_t n, const ForceArrays<D>& f) {
  write_pair_forces_in_blocks<D, Contact, separations_and_force_over_r_avx2<D, Contact>>(
      in, first, last, n, f);
}
#endif

/// Sets f[d][first, n) to the forces of the pairs in rows [first, last), in the fastest form
/// this processor runs (all forms give the same bits).
template <int D, class Contact>
void write_pair_forces(const PairLoopInput<D, Contact>& in, std::size_t first, std::size_t last,
                       std::size_t n, const ForceArrays<D>& f) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    write_pair_forces_avx2(in, first, last, n, f);
    return;
  }
#endif
#if defined(__SSE2__)
  write_pair_forces_sse2(in, first, last, n, f);
#else
  write_pair_forces_scalar(in, first, last, n, f);
#endif
}

}  // namespace jam
