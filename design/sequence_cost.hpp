#pragma once
// What an --until-decided sequence has spent and what its next batch would cost: the core-
// seconds the done runs recorded, and the particle-steps of the runs a batch adds, priced at
// the rate those runs measured.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"

namespace jam::design {

struct Cost {
  double spent_seconds = 0;       // recorded core-seconds (CPU) of the done runs
  double seconds_per_step = NAN;  // measured: spent / their estimated particle-steps
  std::set<std::string> done;     // the runs done (each file verified once per look)
};

/// The cost of the runs of `plan` that are done.
Cost measured_cost(const std::vector<PlannedRun>& plan);

/// Estimated core-seconds of the runs a plan with `counts` adds to what is done (NaN while
/// nothing is measured).
double batch_seconds(const Campaign& c, const SampleCounts& counts, const Cost& cost);

}  // namespace jam::design
