#pragma once
// The planner's price: what one force evaluation costs at each of a campaign's sizes, on the
// clock the runs record. Where it comes from, in this order (each size its own):
//   1. the campaign's own finished runs of that size: the particle-steps and CPU seconds their
//      records hold (campaign_dir.hpp), which is what the rest will cost on this machine;
//   2. the stored measurements of the probe, reference/throughput.toml (by dimension and N);
//   3. the probe itself, on this machine now, repeated, its spread said (`jam campaign plan
//      --probe`, or a dimension the file lacks).
// A plan is then the same number every time it is made of the same campaign and runs: a probe
// per plan on a busy machine moved one design's cost by 45%.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "campaign/run_plan.hpp"
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

/// A campaign's throughput: the probe's at each of its sizes (or what stands for it) and the
/// cost of its integrator's force evaluation in probe steps.
struct Throughput {
  std::map<std::int64_t, double> per_size;     // particle-steps per core-second, by N
  std::map<std::int64_t, std::string> source;  // by N: where per_size comes from, in words
  double evaluation_cost = 1.0;

  /// Core-seconds of `particle_steps` at N = n (a size not probed: the nearest probed one).
  double core_seconds(std::int64_t n, double particle_steps) const;
  /// The probe at N = n (nearest probed size).
  double at(std::int64_t n) const;
};

/// Probes every size of `sizes` once for a campaign whose runs take `run`'s integrator.
Throughput measure_throughput(const SimConfig& run, const std::vector<std::int64_t>& sizes);

/// The probe at N = n repeated: its least, median and largest value.
struct ProbeSpread {
  double min = 0, median = 0, max = 0;
  int repeats = 0;
};
ProbeSpread probe_spread(int dim, std::int64_t n, int repeats);

/// Where the stored measurements are: reference/throughput.toml (install_paths.hpp).
std::string stored_throughput_file();

/// The stored probe of dimension `dim` at N = n from `file` (linear in log N between its
/// sizes, the nearest beyond them); nullopt when the file is absent or has no table for `dim`.
/// A file that is there but does not read is an error naming it and the key.
std::optional<double> stored_throughput(const std::string& file, int dim, std::int64_t n);

/// The plan's price at each size of `sizes`: the stored measurements, or the probe (3 repeats,
/// the median; its spread in the source words) when `probe` or when `file` has none for the
/// dimension.
Throughput plan_throughput(const SimConfig& run, const std::vector<std::int64_t>& sizes, bool probe,
                           const std::string& file = stored_throughput_file());

/// `base` with each size that finished runs of `plan` measured (records with CPU seconds and
/// particle-steps) priced from them instead.
Throughput with_finished_runs(const Throughput& base, const std::vector<PlannedRun>& plan);

}  // namespace jam
