#pragma once
// Measured throughput of this build, for cost estimates: what one force evaluation costs at
// each of a campaign's sizes, on this machine, on the clock the runs record.
#include <cstdint>
#include <map>
#include <vector>

#include "sim/run/sim_config.hpp"

namespace jam {

/// CPU cost of one force evaluation of the Chebyshev integrator in units of the probe's (an
/// overdamped Euler step at the same N): its stages place the particles and keep five
/// vectors, its error norm and dense output read them, the Lanczos estimate of lambda_max
/// adds 30 Hessian products every 25 steps. Measured 2026-11-26 on paper-2d's N = 32768 runs
/// (chained, near and above jamming, rates 10^-5.5 to 1e-7): 2.62-2.76e7 particle-evaluations
/// per CPU second against 3.4-3.6e7 for the probe at that N under the same load, 1.25-1.35;
/// its first rate, mostly at low packings where the neighbor lists are short, 1.04.
inline constexpr double kChebyshevEvaluationCost = 1.3;

/// Particle-steps (force evaluations x particles) per CPU second of one core (this thread's
/// clock) of an overdamped Euler run near jamming (2D phi 0.84, 3D 0.64) of n particles, about
/// 0.3 s of measurement. Sizes above 65536 are probed at 65536 (the caches are long exceeded).
double measure_throughput(int dim, std::int64_t n = 4096);

/// A campaign's throughput: the probe at each of its sizes and the cost of its integrator's
/// force evaluation in probe steps.
struct Throughput {
  std::map<std::int64_t, double> per_size;  // particle-steps per core-second, by N
  double evaluation_cost = 1.0;

  /// Core-seconds of `particle_steps` at N = n (a size not probed: the nearest probed one).
  double core_seconds(std::int64_t n, double particle_steps) const;
  /// The probe at N = n (nearest probed size).
  double at(std::int64_t n) const;
};

/// Probes every size of `sizes` for a campaign whose runs take `run`'s integrator.
Throughput measure_throughput(const SimConfig& run, const std::vector<std::int64_t>& sizes);

}  // namespace jam
