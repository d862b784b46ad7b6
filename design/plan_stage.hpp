#pragma once
// `jam campaign plan FILE` once its options are parsed (app/campaign_command.cpp): the runs,
// particle-steps and core-hours of the design, what its phi_init values show, and what it can
// decide, from a variance model fitted to judged campaigns (--scatter-from), to a pilot run
// first (--pilot K, pilot.hpp) or to the stored reduced result of its dimension.
#include <string>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"
#include "campaign/ranks.hpp"

namespace jam::design {

struct PlanRequest {
  std::vector<std::string> scatter_from;  // judged campaign directories (DIR/checks.json)
  int pilot = 0;                          // K samples of every ensemble run first (0: none)
  bool probe = false;                     // price unmeasured sizes by probing this machine
};

/// Prints the plan; returns 0. A bad --scatter-from (or a pilot that fails) throws, one line
/// naming it, before anything is printed; a missing stored default is only said.
int print_plan_stage(const Campaign& c, const PlanRequest& request, const CampaignRunOptions& run,
                     const Ranks& ranks);

}  // namespace jam::design
