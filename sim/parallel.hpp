#pragma once
// Threads within one run (OpenMP when the compiler has it; one thread otherwise).
//
// Only loops whose iterations are independent and write disjoint elements are split, so their
// results do not depend on the thread count. The one reduction, the elastic forces, sums
// per-thread partial forces in a fixed order (System::compute_elastic_forces): a run is
// bitwise reproducible for a given thread count, and runs with different thread counts agree
// to round-off only (after which chaotic dynamics lets trajectories drift apart, as for any
// change of summation order).
//
// JAM_PARALLEL_FOR splits the following for loop over `threads` threads, a variable that must
// be in scope; with threads == 1 no thread team is started.
#if defined(_OPENMP)
#include <omp.h>
#define JAM_PARALLEL_FOR \
  _Pragma("omp parallel for schedule(static) num_threads(threads) if (threads > 1)")
#else
#define JAM_PARALLEL_FOR
#endif

#include <algorithm>
#include <cstddef>

namespace jam {

/// Threads a run can use on this machine (1 without OpenMP).
inline int available_threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// This thread's number within the current team (0 outside of one).
inline int thread_number() {
#if defined(_OPENMP)
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// Calls f(first, last) on consecutive chunks of [0, n), split over `threads` threads: for
/// per-particle loops whose particles are independent, so that the result does not depend on
/// the thread count, and each call can run a vectorized loop over its chunk.
template <class F>
void for_particle_chunks(std::size_t n, int threads, F&& f) {
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  JAM_PARALLEL_FOR
  for (std::size_t k = 0; k < chunks; ++k) f(k * kChunk, std::min(n, (k + 1) * kChunk));
}

}  // namespace jam
