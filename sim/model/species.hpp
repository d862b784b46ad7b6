#pragma once
// The two particle species of the bidisperse mixture and every per-type and per-pair constant
// derived from them. Units (paper, "Model"): small diameter d_s = 1, contact stiffness k_e = 1,
// time t0 = (D/2) k_d V_s d_s^2 / k_e = 1, so the drag coefficient of a small particle is
// k_d V_s = 2/D.
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace jam {

inline constexpr int kSmall = 0;  // LAMMPS atom type 1
inline constexpr int kBig = 1;    // LAMMPS atom type 2
inline constexpr double kPaperDiameterRatio = 1.4;

/// Volume of a D-sphere of diameter d (an area in 2D).
template <int D>
constexpr double sphere_volume(double diameter) {
  static_assert(D == 2 || D == 3);
  if constexpr (D == 2) {
    return std::numbers::pi * diameter * diameter / 4.0;
  } else {
    return std::numbers::pi * diameter * diameter * diameter / 6.0;
  }
}

/// Per-type and per-pair constants. Pair index = type_i + type_j (0 small-small, 1 mixed,
/// 2 big-big), so the force loop looks them up without branches.
template <int D>
struct Species {
  std::array<double, 2> diameter{};
  std::array<double, 2> volume{};
  std::array<double, 2> drag{};                  // gamma_i = k_d V_i, the drag coefficient of f_dis
  std::array<double, 2> mobility{};              // 1 / gamma_i
  std::array<double, 3> contact_distance{};      // d_ij = (d_i + d_j) / 2
  std::array<double, 3> inv_contact_distance{};  // 1 / d_ij
  double max_contact_distance = 0.0;

  explicit Species(double diameter_ratio = kPaperDiameterRatio) {
    diameter = {1.0, diameter_ratio};
    for (int t = 0; t < 2; ++t) {
      volume[t] = sphere_volume<D>(diameter[t]);
      drag[t] = (2.0 / D) * volume[t] / volume[kSmall];  // k_d V_s = 2/D sets t0 = 1
      mobility[t] = 1.0 / drag[t];
    }
    contact_distance = {diameter[0], 0.5 * (diameter[0] + diameter[1]), diameter[1]};
    for (int p = 0; p < 3; ++p) inv_contact_distance[p] = 1.0 / contact_distance[p];
    max_contact_distance = std::max(diameter[0], diameter[1]);
  }

  /// Masses proportional to volume with the small-particle mass fixed by the quality factor
  /// Q = sqrt(m_s k_e) / (k_d V_s d_s), i.e. m_s = Q^2 (k_d V_s)^2 (paper, "Model").
  std::array<double, 2> masses(double quality_factor) const {
    const double m_small = quality_factor * quality_factor * drag[kSmall] * drag[kSmall];
    return {m_small, m_small * volume[kBig] / volume[kSmall]};
  }
};

}  // namespace jam
