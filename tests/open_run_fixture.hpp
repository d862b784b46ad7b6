#pragma once
// The model attributes of a small 2D open run, for tests that then give it their own series.
#include <cstdint>
#include <string>

#include "sim/io/open_run.hpp"

namespace jam::test {

/// A 2D open run of `n` particles compressed at `rate` from `phi_init`, sample `sample`, by
/// `simulator`; no points yet.
inline OpenRun open_run_of(std::int64_t n, double rate, double phi_init, std::int64_t sample,
                           std::string simulator = "other-code") {
  OpenRun r;
  r.dim = 2;
  r.n = n;
  r.compression_rate = rate;
  r.phi_init = phi_init;
  r.simulator = std::move(simulator);
  r.sample = sample;
  return r;
}

}  // namespace jam::test
