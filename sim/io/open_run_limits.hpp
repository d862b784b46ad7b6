#pragma once
// The open run format's numeric limits: one table, python/jamio/open_run_limits.json, read by
// jam (embedded at build time) and by jamio, so that both validators refuse the same files
// (tests/test_open_run_agreement.py feeds both the same hostile runs).
#include <cstdint>

namespace jam {

struct OpenRunLimits {
  std::int64_t max_whole;   // n and sample at most this (2^53)
  std::int64_t max_points;  // output points per series
  double diameter_ratio_min, diameter_ratio_max;
  double max_contacts_per_particle;
  double jamming_above, jamming_below;  // phi_Ji in (above, below), or NaN
  double phi_init_slack;                // first packing >= phi_init (1 - slack)
  double rate_tolerance;                // phi(t) = phi_init exp(D rate t), relative
};

/// The table, parsed once; a malformed embedded table is a build defect (std::logic_error).
const OpenRunLimits& open_run_limits();

}  // namespace jam
