#pragma once
// Measured throughput of this build, for cost estimates.

namespace jam {

/// Particle-steps per second of one core for an overdamped Euler run near jamming
/// (N = 4096, about 0.3 s of measurement).
double measure_throughput(int dim);

}  // namespace jam
