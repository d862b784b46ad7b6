#pragma once
// What a compression costs each integrator, in force evaluations: the model behind `jam
// campaign plan` and the per-run limits (estimate_run, sim/run/run_limits.cpp). Measured, not
// derived: docs/performance.md, "The planner's estimate against measured campaigns".
#include <algorithm>
#include <cmath>
#include <string_view>

#include "sim/dynamics/integrator_list.hpp"

namespace jam {

/// The Chebyshev integrator's tolerance in the root-mean-square norm over the particles
/// (--error-norm rms) that matches one in the largest component: measured at a tenth, as
/// accurate (2D N = 4096 ensembles at 1e-5 and 1e-6; N = 32768 chained starts at 1e-7 and 1e-8,
/// pressure within 5e-5 of a max-norm 1e-6 reference after the start's first output point, 3e-4
/// at it) with kRmsEvaluationGain fewer force evaluations; at the same value 0.03% biased
/// (docs/performance.md, "The error norm").
inline constexpr double kRmsToleranceRatio = 0.1;
inline constexpr double kRmsEvaluationGain = 1.6;  // 1.56x at N = 4096, 1.64-1.66x at 32768

/// The Chebyshev integrator's cost model in each dimension, fitted 2026-11-26 (commit 88adf7d:
/// dense output, the stiffest-mode estimate) on compressions from 0.40 at their default
/// tolerances, 2D N = 1024 and 4096 at rates 1e-4 to 1e-6 and 3D N = 1024 at 1e-5 and 1e-6 (the
/// evaluations of each stretch of 0.02-0.1 in phi), and on paper-2d's N = 32768 chained runs at
/// 1e-5 to 1e-7: whole runs within 0.74-1.15 of it, its stretches within 0.6-1.3.
struct ChebyshevCost {
  double amplitude;  // evaluations per t0 at `packing` and above, rate 1e-6, tolerance 1e-4, N 4096
  double packing;    // near jamming, where the cost levels off
  double exponent;   // of phi / packing below it, at rate 1e-6
};
inline constexpr ChebyshevCost kChebyshevCost2d{2.1, 0.85, 2.35};
inline constexpr ChebyshevCost kChebyshevCost3d{3.4, 0.65, 3.3};
inline const ChebyshevCost& chebyshev_cost(int dim) {
  return dim == 3 ? kChebyshevCost3d : kChebyshevCost2d;
}

/// Force evaluations per t0 at and above the cost packing: amplitude (rate / 1e-6)^0.25
/// (tolerance / 1e-4)^-0.25 (N / 4096)^0.12, the tolerance in the root-mean-square norm when
/// `rms`. The steps grow with their stages as the rate falls; the largest component of the
/// error sees more rearrangements as N grows.
inline double chebyshev_evaluations_per_time(int dim, double rate, double tolerance, bool rms,
                                             double n) {
  if (rms) tolerance /= kRmsToleranceRatio;
  return chebyshev_cost(dim).amplitude * std::pow(rate / 1e-6, 0.25) *
         std::pow(tolerance / 1e-4, -0.25) * std::pow(n / 4096.0, 0.12) /
         (rms ? kRmsEvaluationGain : 1.0);
}

/// The fraction of that cost at packing phi: (phi / packing)^k, at most 1, k = exponent - 0.5
/// log10(rate / 1e-6) within [1, 4.5]. Far below jamming the steps are long and cheap, the
/// more so the slower the rate (measured 2D, N = 1024 and 4096: at phi 0.45 0.41, 0.32 and
/// 0.22 of the cost at 0.85 at rates 1e-4, 1e-5 and 1e-6; 3D N = 1024 at 0.425: 0.33 and 0.23
/// of the cost at 0.65 at 1e-5 and 1e-6).
inline double chebyshev_packing_factor(int dim, double phi, double rate) {
  const ChebyshevCost& c = chebyshev_cost(dim);
  const double k = std::clamp(c.exponent - 0.5 * std::log10(rate / 1e-6), 1.0, 4.5);
  return std::min(1.0, std::pow(phi / c.packing, k));
}

/// Force evaluations per unit time t0 of a compression of N particles at `rate`, at most (near
/// and above jamming): dt-stepped integrators take force_evaluations / dt; the adaptive
/// Chebyshev integrator chebyshev_evaluations_per_time.
inline double force_evaluations_per_time(std::string_view name, int dim, double dt, double rate,
                                         double tolerance, bool rms, double n) {
  if (is_adaptive_integrator(name))
    return chebyshev_evaluations_per_time(dim, rate, tolerance, rms, n);
  return force_evaluations_per_step(name) / dt;
}

/// Force evaluations of a compression from phi_from to phi_to: force_evaluations_per_time
/// over the time ln(phi_to / phi_from) / (D rate), the adaptive integrator's weighed by
/// chebyshev_packing_factor along the way.
inline double compression_force_evaluations(std::string_view name, int dim, double dt, double rate,
                                            double tolerance, bool rms, double n, double phi_from,
                                            double phi_to) {
  const double top = force_evaluations_per_time(name, dim, dt, rate, tolerance, rms, n);
  const double time = std::log(phi_to / phi_from) / (dim * rate);
  if (!is_adaptive_integrator(name) || !(phi_to > phi_from)) return top * time;
  constexpr int kPieces = 64;  // trapezoids in ln phi; the factor is smooth
  double sum = 0.0;
  for (int k = 0; k <= kPieces; ++k) {
    const double phi = phi_from * std::pow(phi_to / phi_from, static_cast<double>(k) / kPieces);
    sum += (k == 0 || k == kPieces ? 0.5 : 1.0) * chebyshev_packing_factor(dim, phi, rate);
  }
  return top * time * sum / kPieces;
}

/// Force evaluations per unit time t0 of a relaxation at zero rate: force_evaluations / dt,
/// or for the adaptive integrator 20 (Heun's at dt 0.1; its steps grow as the forces fade, so
/// this is an upper bound).
inline double relaxation_evaluations_per_time(std::string_view name, double dt) {
  if (is_adaptive_integrator(name)) return 20.0;
  return force_evaluations_per_step(name) / dt;
}

}  // namespace jam
