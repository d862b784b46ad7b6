#pragma once
// One-sided harmonic contact, U(r) = (1/2) k_e (1 - r/d_ij)^2 for r < d_ij (paper, "Model"),
// k_e = 1. A contact law (contact_law.hpp): the force loop hands it r^2 and the pair index and
// gets back f/r, so that f_ij = (f/r) (r_i - r_j).
#include <algorithm>
#include <array>
#include <cmath>

#include "sim/model/contact_law.hpp"
#include "sim/simd.hpp"

namespace jam {

struct HarmonicContact {
  static constexpr const char* kName = "harmonic";
  static constexpr const char* kFormula = "U = (1/2)(1 - r/d)^2 for r < d";
  // The force is linear in r: LAMMPS's spline through a coarse table reproduces it exactly,
  // and its own r^2-spaced table (pair_style table linear 100000) is the only error.
  static constexpr const char* kLammpsTableStyle = "linear";
  static constexpr int kTablePoints = 201;

  std::array<double, 3> inv_d{};  // 1/d_ij by pair index type_i + type_j

  HarmonicContact() = default;
  template <class SpeciesT>
  explicit HarmonicContact(const SpeciesT& species) : inv_d(species.inv_contact_distance) {}

  /// |f_ij| / r = (1/d)(1 - r/d)/r = (1/d)(1/r - 1/d) for r < d, and 0 otherwise.
  /// Branch-free: beyond contact the bracket is negative and the max clips it (a contact or
  /// not is a coin flip for listed pairs, so a branch here would be mispredicted often).
  double force_over_r(double r2, int pair) const {
    const double inv_r = 1.0 / std::sqrt(r2 + kTinySquaredDistance);
    const double bracket = inv_d[pair] * (inv_r - inv_d[pair]);
    return positive_part(bracket);
  }

#if defined(__SSE2__)
  /// Two pairs at once, the scalar form's operations in the same order (same bits).
  __m128d force_over_r(__m128d r2, std::array<int, 2> pair) const {
    const __m128d id = _mm_set_pd(inv_d[pair[1]], inv_d[pair[0]]);
    const __m128d inv_r = _mm_div_pd(
        _mm_set1_pd(1.0), _mm_sqrt_pd(_mm_add_pd(r2, _mm_set1_pd(kTinySquaredDistance))));
    return _mm_max_pd(_mm_mul_pd(id, _mm_sub_pd(inv_r, id)), _mm_setzero_pd());
  }
#endif
#if defined(JAM_AVX2_FORMS)
  /// Four pairs at once (AVX2, no FMA), the scalar form's bits.
  __attribute__((target("avx2"))) __m256d force_over_r(__m256d r2, std::array<int, 4> pair) const {
    const __m256d id =
        _mm256_set_pd(inv_d[pair[3]], inv_d[pair[2]], inv_d[pair[1]], inv_d[pair[0]]);
    const __m256d inv_r =
        _mm256_div_pd(_mm256_set1_pd(1.0),
                      _mm256_sqrt_pd(_mm256_add_pd(r2, _mm256_set1_pd(kTinySquaredDistance))));
    return _mm256_max_pd(_mm256_mul_pd(id, _mm256_sub_pd(inv_r, id)), _mm256_setzero_pd());
  }
#endif

#if defined(JAM_AVX2_FORMS)
  /// U(r) of four pairs (AVX2, no FMA), the scalar form's bits.
  __attribute__((target("avx2"))) __m256d energy(__m256d r2, std::array<int, 4> pair) const {
    const __m256d overlap = packed_overlap(r2, inv_d, pair);
    return _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0.5), overlap), overlap);
  }
#endif

  /// U(r) for r < d, 0 otherwise.
  double energy(double r2, int pair) const {
    const double overlap = std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]);
    return 0.5 * overlap * overlap;
  }

  /// In contact exactly where the force loop gives a force: one definition for the forces,
  /// Z, the energy sums and the stability bound.
  bool in_contact(double r2, int pair) const {
    return force_over_r(r2, pair) > 0.0;
  }

  /// U''(r) = 1/d^2, the same for every overlap.
  double radial_stiffness(double /*r2*/, int pair) const {
    return inv_d[pair] * inv_d[pair];
  }

  static double energy_at(double r, double d) {
    const double overlap = 1.0 - r / d;
    return 0.5 * overlap * overlap;
  }
  static double force_at(double r, double d) {
    return (1.0 - r / d) / d;
  }
};

static_assert(ContactLaw<HarmonicContact>);

}  // namespace jam
