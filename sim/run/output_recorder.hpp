#pragma once
// What a run keeps at each output point: the observables (observables.hpp) and, when the
// jamming point is asked for, the configuration (observables/jamming_point.hpp).
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "sim/dynamics/system.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/run_state.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {

class OutputRecorder {
 public:
  explicit OutputRecorder(const SimConfig& c)
      : keep_configurations_(c.jamming_point),
        keep_from_(c.jamming_search_from),
        rattlers_(c.rattlers),
        stress_(c.stress),
        dt_(c.dt) {}

  /// Measures the system at time t into st.points. Configurations are kept for the jamming
  /// point from --jamming-search-from on, by default from the start (so the search leans on
  /// nothing but the run itself). A non-finite pressure stops the run: nothing after it could
  /// be trusted.
  template <int D, class Contact>
  void record(System<D, Contact>& sys, RunState<D>& st, double t) const {
    if (keep_configurations_ && sys.box.packing_fraction(t) >= keep_from_) {
      SavedConfiguration saved{sys.box.packing_fraction(t), {}};
      for (int d = 0; d < D; ++d) {
        saved.s.insert(saved.s.end(), sys.particles.s[d].begin(), sys.particles.s[d].end());
      }
      st.saved.push_back(std::move(saved));
    }
    st.points.push_back(measure(sys, t, rattlers_, stress_));
    if (!std::isfinite(st.points.back().pressure)) {
      throw std::runtime_error(fmt::format(
          "the dynamics became unstable (non-finite pressure at phi {:.5f}) with --dt {:g}; "
          "reduce --dt",
          st.points.back().packing_fraction, dt_));
    }
  }

 private:
  bool keep_configurations_;
  double keep_from_;
  bool rattlers_;
  bool stress_;  // the whole tensor is written (--stress): else its diagonal suffices
  double dt_;
};

}  // namespace jam
