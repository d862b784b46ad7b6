#pragma once
// What a contact law is: a tiny pair evaluator in the style of HOOMD-blue's EvaluatorPair*
// classes. The one force loop (sim/dynamics/pair_forces.hpp, every SIMD form), the observables,
// the stability guard, the jamming-point minimisations and the LAMMPS table all take the law as
// a template parameter; nothing outside a law's own header knows its formula.
//
// A law is a struct with (pair = type_i + type_j, r2 = |r_i - r_j|^2):
//   static constexpr const char* kName;        // "harmonic": --contact and the `contact` key
//   static constexpr const char* kFormula;     // U(r) in words, for run files and tables
//   explicit Law(const Species<D>&);           // per-pair constants from the species
//   double force_over_r(double r2, int pair);  // |f_ij| / r >= 0, exactly 0 out of contact
//   __m128d force_over_r(__m128d r2, std::array<int, 2> pair);  // the same operations, packed
//   __m256d force_over_r(__m256d r2, std::array<int, 4> pair);  // (AVX2; same bits)
//   double energy(double r2, int pair);        // U(r), 0 out of contact
//   __m256d energy(__m256d r2, std::array<int, 4> pair);  // the same operations, packed (AVX2)
//   bool in_contact(double r2, int pair);      // the one contact test: force_over_r > 0
//   double radial_stiffness(double r2, int pair);  // U''(r) >= 0 (stability bound)
//   static double energy_at(double r, double d);   // U and f = -dU/dr as functions of r and
//   static double force_at(double r, double d);    // d_ij, for the LAMMPS table
//   static constexpr int kTablePoints;             // points per pair type in that table
//   static constexpr const char* kLammpsTableStyle;  // its pair_style table interpolation
//
// Every law here is purely repulsive (U' <= 0) with U'' >= 0 inside contact: the tangential
// part (U'/r)(1 - n n^T) of the pair Hessian is then negative semidefinite, and the stability
// bounds (sim/dynamics/stability.hpp) need only U''.
#include <array>
#include <concepts>

#include "sim/simd.hpp"

namespace jam {

/// max(x, 0) as one maxsd instruction: compilers otherwise turn the select into a branch.
/// Same value as x > 0 ? x : 0 for every x, NaN included (gives 0).
inline double positive_part(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(x), _mm_setzero_pd()));
#else
  return x > 0.0 ? x : 0.0;
#endif
}

/// r = 0 (two particles at the same point) has no force direction: every law adds this to r^2
/// so that f/r is finite and f = (f/r) * 0 = 0 there; for any r^2 above 1e-184 the sum is r^2
/// exactly.
inline constexpr double kTinySquaredDistance = 1e-200;

template <class L>
concept ContactLaw = requires(const L law, double x, int pair) {
  { L::kName } -> std::convertible_to<const char*>;
  { L::kFormula } -> std::convertible_to<const char*>;
  { law.force_over_r(x, pair) } -> std::same_as<double>;
  { law.energy(x, pair) } -> std::same_as<double>;
  { law.in_contact(x, pair) } -> std::same_as<bool>;
  { law.radial_stiffness(x, pair) } -> std::same_as<double>;
  { L::energy_at(x, x) } -> std::same_as<double>;
  { L::force_at(x, x) } -> std::same_as<double>;
  { L::kTablePoints } -> std::convertible_to<int>;
  { L::kLammpsTableStyle } -> std::convertible_to<const char*>;
};

#if defined(JAM_AVX2_FORMS)
/// The overlap delta = max(1 - r/d_ij, 0) of four pairs, from r^2 and the table of 1/d_ij by
/// pair index: the laws' scalar energy(), std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]),
/// with the same operations (so the same bits).
__attribute__((target("avx2"))) inline __m256d packed_overlap(__m256d r2,
                                                              const std::array<double, 3>& inv_d,
                                                              std::array<int, 4> pair) {
  const __m256d id = _mm256_set_pd(inv_d[pair[3]], inv_d[pair[2]], inv_d[pair[1]], inv_d[pair[0]]);
  return _mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(_mm256_sqrt_pd(r2), id)),
                       _mm256_setzero_pd());
}
#endif

}  // namespace jam
