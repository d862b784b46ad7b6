#pragma once
// The periodic square/cubic box compressed at a constant true strain rate:
// dL/dt = -rate L, so L(t) = L0 exp(-rate t) and phi(t) = phi0 exp(D rate t) (paper, "Model").
// L is always computed from t, never by accumulated multiplication.
#include <cmath>

namespace jam {

template <int D>
struct CompressingBox {
  double initial_length = 1.0;
  double compression_rate = 0.0;
  double particle_volume = 0.0;  // sum of particle volumes

  double length(double t) const { return initial_length * std::exp(-compression_rate * t); }

  double volume(double t) const { return std::pow(length(t), D); }

  double packing_fraction(double t) const {
    return particle_volume / std::pow(initial_length, D) * std::exp(D * compression_rate * t);
  }

  /// Time at which the packing reaches phi (requires compression_rate > 0).
  double time_at_packing(double phi) const {
    return std::log(phi / packing_fraction(0.0)) / (D * compression_rate);
  }

  static double length_for_packing(double particle_volume, double phi) {
    return std::pow(particle_volume / phi, 1.0 / D);
  }
};

}  // namespace jam
