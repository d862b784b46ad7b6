#include "app/campaign_command.hpp"

#include <cstdio>

namespace jam {

void add_campaign_command(CLI::App& app, CampaignArgs& a) {
  CLI::App* campaign = app.add_subcommand(
      "campaign", "Run, inspect and cost ensembles of compression runs described by a TOML file");
  campaign->require_subcommand(1);
  CLI::App* run = campaign->add_subcommand(
      "run", "Run every missing run (resumes partial ones); under mpirun the ranks share them");
  run->option_defaults()->always_capture_default();
  run->add_option("file", a.file, "Campaign file (TOML, see reference/campaigns/)")->required();
  run->add_option("--jobs", a.run.jobs, "Runs at once per process (0 = all cores)");
  run->add_flag("--retry-failed", a.run.retry_failed, "Also redo runs whose last attempt failed");
  run->add_flag("--quiet", a.run.quiet, "No progress display and no summary");
  run->add_option("--shard", a.shard,
                  "K/N: run only the K-th of N disjoint shares of the campaign (whole samples, "
                  "balanced by cost), e.g. one per Slurm array task; together the N shares are "
                  "the whole campaign, bitwise");
  run->add_flag("--force", a.run.force,
                "Run even runs beyond the per-run limits on steps, output points and memory");
  CLI::App* status = campaign->add_subcommand(
      "status", "Print what is done, partial, missing, failed or corrupt in a campaign directory");
  status->add_option("directory", a.directory, "Campaign directory (its 'output')")->required();
  status->add_flag("--json", a.json, "The same as JSON (totals, and every run's status)");
  status->footer(
      "Exit status: 0 every run is done; 1 a run failed or is corrupt; 4 runs are "
      "missing or partial (none failed); 2 the directory is not a campaign's.");
  CLI::App* plan = campaign->add_subcommand(
      "plan", "Print the number of runs, particle-steps and estimated core-hours");
  plan->add_option("file", a.file, "Campaign file (TOML)")->required();
}

int run_campaign_command(const CLI::App& app, const CampaignArgs& a, const Ranks& ranks) {
  const CLI::App* campaign = app.get_subcommand("campaign");
  if (campaign->got_subcommand("run")) {
    CampaignRunOptions options = a.run;
    if (!a.shard.empty()) {
      int k = 0, n = 0;
      char rest = 0;
      if (std::sscanf(a.shard.c_str(), "%d/%d%c", &k, &n, &rest) != 2 || n < 1 || k < 1 || k > n) {
        throw CLI::ValidationError("--shard",
                                   a.shard + ": must read K/N with 1 <= K <= N, e.g. 3/8");
      }
      options.shard = k;
      options.shards = n;
    }
    return run_campaign(read_campaign(a.file), options, ranks);
  }
  if (campaign->got_subcommand("status")) return print_campaign_status(a.directory, a.json);
  return print_campaign_plan(read_campaign(a.file));
}

}  // namespace jam
