#pragma once
// Measured throughput of this build, for cost estimates.

namespace jam {

/// Particle-steps per CPU second (this thread's clock) of an overdamped Euler run near
/// jamming (N = 4096, about 0.3 s of measurement).
double measure_throughput(int dim);

}  // namespace jam
