#pragma once
// Runs what a campaign still needs: on a local pool of threads (one run per thread, longest
// runs first), and, when started under mpirun, shared among the MPI ranks.
#include "campaign/campaign_file.hpp"
#include "campaign/ranks.hpp"

namespace jam {

struct CampaignRunOptions {
  int jobs = 0;               // worker threads per process; 0: all cores
  bool retry_failed = false;  // also redo runs whose last attempt failed
  bool quiet = false;
  bool force = false;  // run beyond the per-run limits of validate_cost (sim_config.hpp)
};

/// Returns the exit status: 0 when every run is done, 1 when some failed, 130 when
/// interrupted (the interrupted runs keep checkpoints and resume next time).
int run_campaign(const Campaign& campaign, const CampaignRunOptions& options, const Ranks& ranks);

/// Prints what is done, partial, failed, corrupt and missing. Returns 0.
int print_campaign_status(const std::string& directory);

/// Prints the cost of a campaign before it runs, from the measured throughput of this build.
int print_campaign_plan(const Campaign& campaign);

}  // namespace jam
