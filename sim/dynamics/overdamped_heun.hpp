#pragma once
// Heun's method (explicit trapezoid) for the overdamped equation of motion: an Euler
// predictor at t + dt, then the average of the two slopes. Second order in dt, two force
// evaluations per step. Slopes in scaled coordinates: ds_i/dt = f_i^el(t) / (gamma_i L(t)).
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

  OverdampedHeun(std::size_t n, const StepperOptions& /*o*/) : OverdampedHeun(n) {}
  explicit OverdampedHeun(std::size_t n) {
    for (int d = 0; d < D; ++d) {
      s0_[d].resize(n);
      slope0_[d].resize(n);
    }
  }
  void reset() {}
  StepperState save_state() const { return {}; }
  void load_state(const StepperState& /*state*/) {}

  template <class Contact>

  void step(System<D, Contact>& sys, double t, double dt) {
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    const double length0 = sys.box.length(t);
    const double length1 = sys.box.length(t + dt);

    sys.compute_elastic_forces(length0);
    const std::array<double, 2> c0 = {sys.species.mobility[0] / length0,
                                      sys.species.mobility[1] / length0};
    for_particle_chunks(n, sys.threads(), [&](std::size_t first, std::size_t last) {
      for (int d = 0; d < D; ++d) {
        heun_predict(sys.particles.s[d].data(), s0_[d].data(), slope0_[d].data(),
                     sys.force[d].data(), type, c0, dt, first, last);
      }
    });

    sys.compute_elastic_forces(length1);
    const std::array<double, 2> c1 = {sys.species.mobility[0] / length1,
                                      sys.species.mobility[1] / length1};
    const double half_dt = 0.5 * dt;
    for_particle_chunks(n, sys.threads(), [&](std::size_t first, std::size_t last) {
      for (int d = 0; d < D; ++d) {
        heun_correct(sys.particles.s[d].data(), s0_[d].data(), slope0_[d].data(),
                     sys.force[d].data(), type, c1, half_dt, first, last);
      }
    });
  }

 private:
  std::array<std::vector<double>, D> s0_;
  std::array<std::vector<double>, D> slope0_;
};

}  // namespace jam
