#pragma once
// Forward Euler for the overdamped equation of motion (the paper's Q -> 0 limit),
//   dr_i/dt = v_host(r_i) + f_i^el / gamma_i.
// In scaled coordinates s = r/L + 1/2 the host flow drops out: ds_i/dt = f_i^el / (gamma_i L).
// First order in dt; one force evaluation per step; no velocity arrays.
#include <algorithm>
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
  void reset() {}
  StepperState save_state() const { return {}; }
  void load_state(const StepperState& /*state*/) {}

  /// Advances the system from time t to t + dt.
  void step(System<D>& sys, double t, double dt) {
    const double box_length = sys.box.length(t);
    sys.compute_elastic_forces(box_length);
    const std::array<double, 2> c = {dt * sys.species.mobility[0] / box_length,
                                     dt * sys.species.mobility[1] / box_length};
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    const int threads = sys.threads();
    // In chunks of particles (independent, so the thread count does not change the result).
    constexpr std::size_t kChunk = 4096;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    JAM_PARALLEL_FOR
    for (std::size_t k = 0; k < chunks; ++k) {
      for (int d = 0; d < D; ++d) {
        advance_coordinate(sys.particles.s[d].data(), sys.force[d].data(), type, c, k * kChunk,
                           std::min(n, (k + 1) * kChunk));
      }
    }
  }
};

}  // namespace jam
