#pragma once
// One-sided Hertzian contact, U(r) = (2/5) k_e (1 - r/d_ij)^(5/2) for r < d_ij, k_e = 1:
// the force (1/d)(1 - r/d)^(3/2) of two elastic spheres pressed together, the other contact
// law of jamming studies since O'Hern, Silbert, Liu and Nagel, PRE 68, 011306 (2003). Its
// quasi-static pressure above jamming grows as (phi - phi_J)^(3/2) instead of the harmonic
// law's (phi - phi_J)^1. A contact law (contact_law.hpp).
#include <algorithm>
#include <array>
#include <cmath>

#include "sim/model/contact_law.hpp"
#include "sim/simd.hpp"

namespace jam {

struct HertzianContact {
  static constexpr const char* kName = "hertzian";
  static constexpr const char* kFormula = "U = (2/5)(1 - r/d)^(5/2) for r < d";
  // f ~ delta^(3/2) is not a polynomial, and its derivatives grow without bound at the contact
  // edge, so LAMMPS interpolates it by splines (pair_style table spline) through a fine table:
  // measured on `jam check lammps` (N = 256, Q = 0.1, 400 steps), 10001 points leave 1.5e-9 in
  // the positions, 100001 points 5e-12 to 1e-11, the round-off of the harmonic comparison.
  static constexpr const char* kLammpsTableStyle = "spline";
  static constexpr int kTablePoints = 100001;

  std::array<double, 3> inv_d{};  // 1/d_ij by pair index type_i + type_j

  HertzianContact() = default;
  template <class SpeciesT>
  explicit HertzianContact(const SpeciesT& species) : inv_d(species.inv_contact_distance) {}

  /// |f_ij| / r = (1/d) delta^(3/2) / r with the overlap delta = max(1 - r/d, 0).
  /// Branch-free like the harmonic law; r carries kTinySquaredDistance so that r = 0 gives a
  /// finite f/r (and f = 0).
  double force_over_r(double r2, int pair) const {
    const double r = std::sqrt(r2 + kTinySquaredDistance);
    const double overlap = positive_part(1.0 - r * inv_d[pair]);
    return inv_d[pair] * (overlap * std::sqrt(overlap)) / r;
  }

#if defined(__SSE2__)
  /// Two pairs at once, the scalar form's operations in the same order (same bits).
  __m128d force_over_r(__m128d r2, std::array<int, 2> pair) const {
    const __m128d id = _mm_set_pd(inv_d[pair[1]], inv_d[pair[0]]);
    const __m128d r = _mm_sqrt_pd(_mm_add_pd(r2, _mm_set1_pd(kTinySquaredDistance)));
    const __m128d overlap =
        _mm_max_pd(_mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(r, id)), _mm_setzero_pd());
    return _mm_div_pd(_mm_mul_pd(id, _mm_mul_pd(overlap, _mm_sqrt_pd(overlap))), r);
  }
#endif
#if defined(JAM_AVX2_FORMS)
  /// Four pairs at once (AVX2, no FMA), the scalar form's bits.
  __attribute__((target("avx2"))) __m256d force_over_r(__m256d r2, std::array<int, 4> pair) const {
    const __m256d id =
        _mm256_set_pd(inv_d[pair[3]], inv_d[pair[2]], inv_d[pair[1]], inv_d[pair[0]]);
    const __m256d r = _mm256_sqrt_pd(_mm256_add_pd(r2, _mm256_set1_pd(kTinySquaredDistance)));
    const __m256d overlap = _mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(r, id)),
                                          _mm256_setzero_pd());
    return _mm256_div_pd(_mm256_mul_pd(id, _mm256_mul_pd(overlap, _mm256_sqrt_pd(overlap))), r);
  }
#endif

#if defined(JAM_AVX2_FORMS)
  /// U(r) of four pairs (AVX2, no FMA), the scalar form's bits.
  __attribute__((target("avx2"))) __m256d energy(__m256d r2, std::array<int, 4> pair) const {
    const __m256d overlap = packed_overlap(r2, inv_d, pair);
    return _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0.4), overlap), overlap),
                         _mm256_sqrt_pd(overlap));
  }
#endif

  /// U(r) = (2/5) delta^(5/2) for r < d, 0 otherwise.
  double energy(double r2, int pair) const {
    const double overlap = std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]);
    return 0.4 * overlap * overlap * std::sqrt(overlap);
  }

  /// In contact exactly where the force loop gives a force.
  bool in_contact(double r2, int pair) const {
    return force_over_r(r2, pair) > 0.0;
  }

  /// U''(r) = (3/2) delta^(1/2) / d^2: the stiffness grows with the overlap (and vanishes at
  /// first touch), so the stability bound follows the deepest contacts.
  double radial_stiffness(double r2, int pair) const {
    const double overlap = std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]);
    return 1.5 * std::sqrt(overlap) * inv_d[pair] * inv_d[pair];
  }

  static double energy_at(double r, double d) {
    const double overlap = 1.0 - r / d;
    return 0.4 * overlap * overlap * std::sqrt(overlap);
  }
  static double force_at(double r, double d) {
    const double overlap = 1.0 - r / d;
    return overlap * std::sqrt(overlap) / d;
  }
};

static_assert(ContactLaw<HertzianContact>);

}  // namespace jam
