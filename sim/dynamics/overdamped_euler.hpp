#pragma once
// Forward Euler for the overdamped equation of motion (the paper's Q -> 0 limit),
//   dr_i/dt = v_host(r_i) + f_i^el / gamma_i.
// In scaled coordinates s = r/L + 1/2 the host flow drops out: ds_i/dt = f_i^el / (gamma_i L).
// First order in dt; one force evaluation per step; no velocity arrays.
#include <array>
#include <cstddef>

#include "sim/dynamics/position_update.hpp"
#include "sim/dynamics/stepper_state.hpp"
#include "sim/dynamics/system.hpp"
#include "sim/parallel.hpp"

namespace jam {

template <int D>
class OverdampedEuler {
 public:
  static constexpr const char* kName = "euler";
  static constexpr int kOrder = 1;

  explicit OverdampedEuler(std::size_t /*n*/) {}
  OverdampedEuler(std::size_t n, const StepperOptions& /*o*/) : OverdampedEuler(n) {}
  void reset() {}
  StepperState save_state() const { return {}; }
  void load_state(const StepperState& /*state*/) {}

  /// Advances the system from time t to t + dt.
  template <class Contact>
  void step(System<D, Contact>& sys, double t, double dt) {
    const double box_length = sys.box.length(t);
    sys.compute_elastic_forces(box_length);
    const std::array<double, 2> c = {dt * sys.species.mobility[0] / box_length,
                                     dt * sys.species.mobility[1] / box_length};
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    for_particle_chunks(n, sys.threads(), [&](std::size_t first, std::size_t last) {
      for (int d = 0; d < D; ++d)
        advance_coordinate(sys.particles.s[d].data(), sys.force[d].data(), type, c, first, last);
    });
  }
};

}  // namespace jam
