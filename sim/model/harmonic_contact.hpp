#pragma once
// One-sided harmonic contact, U(r) = (1/2) k_e (1 - r/d_ij)^2 for r < d_ij (paper, "Model").
// A tiny evaluator in the style of HOOMD's pair evaluators: the force loop hands it r^2 and
// the pair index and gets back f/r, so that f_ij = (f/r) (r_i - r_j).
#include <algorithm>
#include <array>
#include <cmath>

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

struct HarmonicContact {
  std::array<double, 3> inv_d{};  // 1/d_ij by pair index type_i + type_j

  HarmonicContact() = default;
  template <class SpeciesT>
  explicit HarmonicContact(const SpeciesT& species) : inv_d(species.inv_contact_distance) {}

  /// |f_ij| / r = (1/d)(1 - r/d)/r = (1/d)(1/r - 1/d) for r < d, and 0 otherwise.
  /// Branch-free: beyond contact the bracket is negative and the max clips it (a contact or
  /// not is a coin flip for listed pairs, so a branch here would be mispredicted often).
  /// r = 0 (two particles at the same point) has no force direction: 1e-200 is added to r^2 so
  /// that f/r is finite and f = (f/r) * 0 = 0 there; for any r^2 above 1e-184 the sum is r^2
  /// exactly.
  double force_over_r(double r2, int pair) const {
    const double inv_r = 1.0 / std::sqrt(r2 + 1e-200);
    const double bracket = inv_d[pair] * (inv_r - inv_d[pair]);
    return positive_part(bracket);
  }

  /// U(r) for r < d, 0 otherwise.
  double energy(double r2, int pair) const {
    const double overlap = std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]);
    return 0.5 * overlap * overlap;
  }

  bool in_contact(double r2, int pair) const { return 1.0 - std::sqrt(r2) * inv_d[pair] > 0.0; }
};

}  // namespace jam
