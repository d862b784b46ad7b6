#pragma once
// FIRE energy minimization at fixed box (Bitzek et al., PRL 97, 170201 (2006)), with unit
// masses and the standard parameters: N_min = 5, f_inc = 1.1, f_dec = 0.5, alpha_start = 0.1,
// f_alpha = 0.99. Converged when the largest force component is below force_tolerance; below
// jamming that is reached when every overlap is gone (all forces exactly zero).
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <vector>

#include "sim/dynamics/system.hpp"

namespace jam {

struct FireResult {
  bool converged = false;
  bool stopped = false;  // FireOptions::stop became true: the minimization was abandoned
  std::size_t iterations = 0;
  double max_force = 0.0;
};

struct FireOptions {
  double force_tolerance = 1e-10;
  std::size_t max_iterations = 200000;
  double dt_start = 0.05, dt_max = 0.5;
  /// When set and true, the minimization returns at once (a run asked to stop by SIGTERM).
  const std::atomic<bool>* stop = nullptr;
};

template <int D, class Contact>
FireResult minimize_fire(System<D, Contact>& sys, double box_length, const FireOptions& o = {}) {
  const std::size_t n = sys.size();
  std::array<std::vector<double>, D> v;
  for (auto& c : v) c.assign(n, 0.0);
  double dt = o.dt_start, alpha = 0.1;
  std::size_t positive = 0;
  FireResult r;
  sys.compute_elastic_forces(box_length);
  for (r.iterations = 0; r.iterations < o.max_iterations; ++r.iterations) {
    double power = 0.0, v2 = 0.0, f2 = 0.0, fmax = 0.0;
    for (int d = 0; d < D; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        const double f = sys.force[d][i];
        power += f * v[d][i];
        v2 += v[d][i] * v[d][i];
        f2 += f * f;
        fmax = std::max(fmax, std::abs(f));
      }
    }
    r.max_force = fmax;
    if (fmax < o.force_tolerance) {
      r.converged = true;
      return r;
    }
    if (o.stop && o.stop->load(std::memory_order_relaxed)) {
      r.stopped = true;
      return r;
    }
    if (power > 0.0) {
      const double mix = alpha * std::sqrt(v2 / f2);
      for (int d = 0; d < D; ++d)
        for (std::size_t i = 0; i < n; ++i)
          v[d][i] = (1.0 - alpha) * v[d][i] + mix * sys.force[d][i];
      if (++positive > 5) {
        dt = std::min(1.1 * dt, o.dt_max);
        alpha *= 0.99;
      }
    } else {
      for (auto& c : v) std::fill(c.begin(), c.end(), 0.0);
      dt *= 0.5;
      alpha = 0.1;
      positive = 0;
    }
    // Semi-implicit Euler step with unit masses, positions in scaled coordinates.
    for (int d = 0; d < D; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        v[d][i] += dt * sys.force[d][i];
        sys.particles.s[d][i] = wrap_unit(sys.particles.s[d][i] + dt * v[d][i] / box_length);
      }
    }
    sys.compute_elastic_forces(box_length);
  }
  return r;
}

}  // namespace jam
