#pragma once
// Regression against a stored campaign result: a campaign rerun (all or part of it) compared
// with the stats.h5 of a baseline, ensemble by ensemble (size, phi_init, rate).
//
//  - Rerun samples (the same sample number, hence the same seed and start): their pressure
//    curves must equal the baseline's to `tolerance` (relative; 0 = bitwise). The simulator is
//    deterministic, so any change to the physics, the integrator, the output grid or the
//    averaging shows here at once.
//  - New samples (numbers the baseline does not have): their mean pressure must agree with the
//    baseline's within errors, by the permutation max-t test of the finite-size check
//    (relative_difference.hpp), Bonferroni over the ensembles compared.
#include <vector>

#include "checks/checks.hpp"

namespace jam::checks {

struct RegressionOptions {
  double tolerance = 0.0;  // largest |p_now / p_baseline - 1| for rerun samples
};

std::vector<Verdict> regression_check(const StatsData& now, const StatsData& baseline,
                                      const CheckOptions& o, const RegressionOptions& r);

}  // namespace jam::checks
