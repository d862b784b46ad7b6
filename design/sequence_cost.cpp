#include "design/sequence_cost.hpp"

#include "campaign/campaign_dir.hpp"

namespace jam::design {

Cost measured_cost(const std::vector<PlannedRun>& plan) {
  Cost c;
  double steps = 0;
  for (const auto& run : plan) {
    if (run_status(run) != RunStatus::kDone) continue;
    c.done.insert(run.name);
    if (const auto w = recorded_core_seconds(run)) {
      c.spent_seconds += *w;
      steps += run.estimated_particle_steps;
    }
  }
  if (steps > 0) c.seconds_per_step = c.spent_seconds / steps;
  return c;
}

/// Estimated core-seconds of the runs a plan with `counts` adds to what is done.
double batch_seconds(const Campaign& c, const SampleCounts& counts, const Cost& cost) {
  double steps = 0;
  for (const auto& run : plan_runs(c, counts))
    if (!cost.done.count(run.name)) steps += run.estimated_particle_steps;
  return steps * cost.seconds_per_step;
}

}  // namespace jam::design
