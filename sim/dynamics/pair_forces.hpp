#pragma once
// The pair loop of the elastic forces over rows of the half neighbor list, in two forms that
// give the same bits:
//  - accumulate_pair_forces_scalar: one pair at a time (the reference form);
//  - accumulate_pair_forces_paired: the separations and f/r of a block of pairs first, two
//    pairs per SSE2 instruction (sqrt and division, the costly part, run two at a time), then
//    the forces added pair by pair in the list's order.
// Every operation is an IEEE-754 operation on doubles, correctly rounded the same way in a
// packed register as alone, and the additions into the forces happen in the same order, so the
// two forms agree bit for bit (tests/test_pair_forces.cpp checks it).
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "sim/model/harmonic_contact.hpp"
#include "sim/model/particles.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace jam {

/// Where the pair loop adds forces: one array per dimension (std::type_identity_t keeps D
/// deduced from PairLoopInput alone).
template <int D>
using ForceArrays = std::type_identity_t<std::array<double*, D>>;

/// What the pair loop reads: the list (CSR rows and the row of every pair), species, positions.
template <int D>
struct PairLoopInput {
  const std::uint32_t* offsets;      // row i is pairs [offsets[i], offsets[i+1])
  const std::uint32_t* neighbors;    // j of every pair
  const std::uint32_t* row_of_pair;  // i of every pair
  const std::uint8_t* type;
  std::array<const double*, D> s;  // scaled positions
  std::array<double, 3> inv_d;     // 1/d_ij by type_i + type_j
  double box_length;
};

/// Adds the forces of the pairs in rows [first, last) into f (both partners), one pair at a
/// time: f_ij = (f/r) (r_i - r_j) with f/r from HarmonicContact.
template <int D>
void accumulate_pair_forces_scalar(const PairLoopInput<D>& in, std::size_t first, std::size_t last,
                                   const ForceArrays<D>& f) {
  HarmonicContact contact;
  contact.inv_d = in.inv_d;
  for (std::size_t i = first; i < last; ++i) {
    std::array<double, D> si, fi{};
    for (int d = 0; d < D; ++d) si[d] = in.s[d][i];
    const int ti = in.type[i];
    for (std::uint32_t k = in.offsets[i]; k < in.offsets[i + 1]; ++k) {
      const std::uint32_t j = in.neighbors[k];
      std::array<double, D> dr;
      double r2 = 0.0;
      for (int d = 0; d < D; ++d) {
        dr[d] = in.box_length * minimum_image(si[d] - in.s[d][j]);
        r2 += dr[d] * dr[d];
      }
      const double c = contact.force_over_r(r2, ti + in.type[j]);
      for (int d = 0; d < D; ++d) {
        fi[d] += c * dr[d];
        f[d][j] -= c * dr[d];
      }
    }
    for (int d = 0; d < D; ++d) f[d][i] += fi[d];
  }
}

#if defined(__SSE2__)
/// The same sums as accumulate_pair_forces_scalar, bit for bit, with f/r of two pairs per
/// instruction. Pairs are taken in blocks of whole rows of about kBlock pairs, so that their
/// separations stay in the L1 cache between the two passes.
template <int D>
void accumulate_pair_forces_paired(const PairLoopInput<D>& in, std::size_t first, std::size_t last,
                                   const ForceArrays<D>& f) {
  constexpr std::size_t kBlock = 256;
  alignas(16) std::array<std::array<double, kBlock + 64>, D> dr;  // + the longest row
  alignas(16) std::array<double, kBlock + 64> c;
  HarmonicContact contact;
  contact.inv_d = in.inv_d;
  const __m128d length = _mm_set1_pd(in.box_length);
  const __m128d tiny = _mm_set1_pd(1e-200);  // force_over_r's floor of r^2
  const __m128d one = _mm_set1_pd(1.0);
  std::size_t row = first;
  while (row < last) {
    // Whole rows [row, row_end) of at most kBlock pairs (a longer row goes alone; rows are far
    // shorter than the 64 spare entries).
    const std::uint32_t k0 = in.offsets[row];
    std::size_t row_end = row + 1;
    while (row_end < last && in.offsets[row_end + 1] - k0 <= kBlock) ++row_end;
    const std::uint32_t k1 = in.offsets[row_end];
    if (k1 - k0 > kBlock + 64) {  // a pathological row: the reference form
      accumulate_pair_forces_scalar(in, row, row_end, f);
      row = row_end;
      continue;
    }
    // Pass 1: separations and f/r, two pairs at a time.
    std::uint32_t k = k0;
    for (; k + 1 < k1; k += 2) {
      const std::uint32_t i0 = in.row_of_pair[k], i1 = in.row_of_pair[k + 1];
      const std::uint32_t j0 = in.neighbors[k], j1 = in.neighbors[k + 1];
      __m128d r2 = _mm_setzero_pd();
      for (int d = 0; d < D; ++d) {
        const __m128d ds =
            _mm_sub_pd(_mm_set_pd(in.s[d][i1], in.s[d][i0]), _mm_set_pd(in.s[d][j1], in.s[d][j0]));
        const __m128d v = _mm_mul_pd(length, minimum_image(ds));
        _mm_store_pd(&dr[d][k - k0], v);
        r2 = _mm_add_pd(r2, _mm_mul_pd(v, v));
      }
      const __m128d inv_d =
          _mm_set_pd(in.inv_d[in.type[i1] + in.type[j1]], in.inv_d[in.type[i0] + in.type[j0]]);
      const __m128d inv_r = _mm_div_pd(one, _mm_sqrt_pd(_mm_add_pd(r2, tiny)));
      const __m128d bracket = _mm_mul_pd(inv_d, _mm_sub_pd(inv_r, inv_d));
      _mm_store_pd(&c[k - k0], _mm_max_pd(bracket, _mm_setzero_pd()));
    }
    if (k < k1) {  // an odd last pair
      const std::uint32_t i = in.row_of_pair[k], j = in.neighbors[k];
      double r2 = 0.0;
      for (int d = 0; d < D; ++d) {
        dr[d][k - k0] = in.box_length * minimum_image(in.s[d][i] - in.s[d][j]);
        r2 += dr[d][k - k0] * dr[d][k - k0];
      }
      c[k - k0] = contact.force_over_r(r2, in.type[i] + in.type[j]);
    }
    // Pass 2: the forces, in the order of the scalar form.
    for (std::size_t i = row; i < row_end; ++i) {
      std::array<double, D> fi{};
      for (std::uint32_t q = in.offsets[i]; q < in.offsets[i + 1]; ++q) {
        const std::uint32_t j = in.neighbors[q];
        for (int d = 0; d < D; ++d) {
          fi[d] += c[q - k0] * dr[d][q - k0];
          f[d][j] -= c[q - k0] * dr[d][q - k0];
        }
      }
      for (int d = 0; d < D; ++d) f[d][i] += fi[d];
    }
    row = row_end;
  }
}
#endif

/// The fastest form this build has.
template <int D>
void accumulate_pair_forces(const PairLoopInput<D>& in, std::size_t first, std::size_t last,
                            const ForceArrays<D>& f) {
#if defined(__SSE2__)
  accumulate_pair_forces_paired(in, first, last, f);
#else
  accumulate_pair_forces_scalar(in, first, last, f);
#endif
}

}  // namespace jam
