#pragma once
// Heun's method (explicit trapezoid) for the overdamped equation of motion: an Euler
// predictor at t + dt, then the average of the two slopes. Second order in dt, two force
// evaluations per step. Slopes in scaled coordinates: ds_i/dt = f_i^el(t) / (gamma_i L(t)).
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "sim/dynamics/position_update.hpp"
#include "sim/dynamics/stepper_state.hpp"
#include "sim/dynamics/system.hpp"
#include "sim/parallel.hpp"

namespace jam {

template <int D>
class OverdampedHeun {
 public:
  static constexpr const char* kName = "heun";
  static constexpr int kOrder = 2;

  explicit OverdampedHeun(std::size_t n) {
    for (int d = 0; d < D; ++d) {
      s0_[d].resize(n);
      slope0_[d].resize(n);
    }
  }
  void reset() {}
  StepperState save_state() const { return {}; }
  void load_state(const StepperState& /*state*/) {}

  void step(System<D>& sys, double t, double dt) {
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    const double length0 = sys.box.length(t);
    const double length1 = sys.box.length(t + dt);

    sys.compute_elastic_forces(length0);
    const std::array<double, 2> c0 = {sys.species.mobility[0] / length0,
                                      sys.species.mobility[1] / length0};
    const int threads = sys.threads();
    // In chunks of particles (independent, so the thread count does not change the result).
    constexpr std::size_t kChunk = 4096;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    JAM_PARALLEL_FOR
    for (std::size_t k = 0; k < chunks; ++k) {
      for (int d = 0; d < D; ++d) {
        heun_predict(sys.particles.s[d].data(), s0_[d].data(), slope0_[d].data(),
                     sys.force[d].data(), type, c0, dt, k * kChunk, std::min(n, (k + 1) * kChunk));
      }
    }

    sys.compute_elastic_forces(length1);
    const std::array<double, 2> c1 = {sys.species.mobility[0] / length1,
                                      sys.species.mobility[1] / length1};
    const double half_dt = 0.5 * dt;
    JAM_PARALLEL_FOR
    for (std::size_t k = 0; k < chunks; ++k) {
      for (int d = 0; d < D; ++d) {
        heun_correct(sys.particles.s[d].data(), s0_[d].data(), slope0_[d].data(),
                     sys.force[d].data(), type, c1, half_dt, k * kChunk,
                     std::min(n, (k + 1) * kChunk));
      }
    }
  }

 private:
  std::array<std::vector<double>, D> s0_;
  std::array<std::vector<double>, D> slope0_;
};

}  // namespace jam
