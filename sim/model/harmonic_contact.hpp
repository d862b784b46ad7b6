#pragma once
// One-sided harmonic contact, U(r) = (1/2) k_e (1 - r/d_ij)^2 for r < d_ij (paper, "Model").
// A tiny evaluator in the style of HOOMD's pair evaluators: the force loop hands it r^2 and
// the pair index and gets back f/r, so that f_ij = (f/r) (r_i - r_j).
#include <algorithm>
#include <array>
#include <cmath>

namespace jam {

struct HarmonicContact {
  std::array<double, 3> inv_d{};  // 1/d_ij by pair index type_i + type_j

  template <class SpeciesT>
  explicit HarmonicContact(const SpeciesT& species) : inv_d(species.inv_contact_distance) {}

  /// |f_ij| / r = (1/d)(1 - r/d)/r = (1/d)(1/r - 1/d) for r < d, and 0 otherwise.
  /// Branch-free: beyond contact the bracket is negative and max() clips it. r = 0 (two
  /// particles at the same point) has no force direction: r^2 is floored so that f/r is
  /// finite and f = (f/r) * 0 = 0 there.
  double force_over_r(double r2, int pair) const {
    const double inv_r = 1.0 / std::sqrt(std::max(r2, 1e-200));
    return std::max(0.0, inv_d[pair] * (inv_r - inv_d[pair]));
  }

  /// U(r) for r < d, 0 otherwise.
  double energy(double r2, int pair) const {
    const double overlap = std::max(0.0, 1.0 - std::sqrt(r2) * inv_d[pair]);
    return 0.5 * overlap * overlap;
  }

  bool in_contact(double r2, int pair) const { return 1.0 - std::sqrt(r2) * inv_d[pair] > 0.0; }
};

}  // namespace jam
