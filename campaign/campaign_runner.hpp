#pragma once
// Runs what a campaign still needs: on a local pool of threads (one run per thread, longest
// runs first), and, when started under mpirun, shared among the MPI ranks.
#include <map>

#include "campaign/campaign_dir.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/ranks.hpp"
#include "campaign/throughput.hpp"

namespace jam {

struct CampaignRunOptions {
  int jobs = 0;               // worker threads per process; 0: all cores
  bool retry_failed = false;  // also redo runs whose last attempt failed
  bool quiet = false;
  bool force = false;         // run beyond the per-run limits of validate_cost (sim_config.hpp)
  int shard = 1, shards = 1;  // run only the shard-th of `shards` shares (run_plan.hpp)
  double log_seconds = 300;   // without a terminal: a progress line this often
};

/// Returns the exit status: 0 when every run is done, 1 when some failed, 130 when
/// interrupted (the interrupted runs keep checkpoints and resume next time).
int run_campaign(const Campaign& campaign, const CampaignRunOptions& options, const Ranks& ranks);

/// Exit statuses of `jam campaign status`: 0 every run is done; kStatusProblems when a run
/// failed or is corrupt; kStatusUnfinished when runs are missing or partial (and none failed).
constexpr int kStatusProblems = 1;
constexpr int kStatusUnfinished = 4;
int campaign_status_code(const std::map<RunStatus, std::size_t>& totals);

/// Prints what is done, partial, failed, corrupt and missing in DIR (resolved against DIR from
/// any working directory), as a table or as JSON; returns campaign_status_code.
int print_campaign_status(const std::string& directory, bool json = false);

/// Prints the cost of a campaign, priced at each of its sizes from its finished runs, else
/// the stored measurements, else (or when `probe`) this machine's probe with its spread
/// (throughput.hpp; the price used is returned in `measured_speed`).
int print_campaign_plan(const Campaign& campaign, Throughput* measured_speed = nullptr,
                        bool probe = false);

}  // namespace jam
