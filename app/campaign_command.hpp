#pragma once
#include <CLI/CLI.hpp>

#include "campaign/campaign_runner.hpp"
#include "campaign/convergence_campaign.hpp"
#include "campaign/external_campaign.hpp"
#include "design/plan_stage.hpp"
#include "design/until_decided.hpp"

namespace jam {

struct CampaignArgs {
  std::string file;       // campaign TOML (run, plan)
  std::string directory;  // campaign directory (status)
  CampaignRunOptions run;
  bool json = false;  // status --json
  std::string shard;  // run --shard K/N
  bool until_decided = false;
  design::UntilDecidedOptions until;      // --budget, --alpha
  design::PlanRequest plan;               // plan --scatter-from DIR..., --pilot K, --probe
  std::vector<std::string> import_files;  // import DIR FILE...
  ImportOptions import_options;
  ConvergenceChoice converge;  // converge FILE: what is redone
  std::string converge_out;    // converge --out: the campaign file written
};

/// Registers `jam campaign run|status|plan`.
void add_campaign_command(CLI::App& app, CampaignArgs& args);

/// Runs whichever campaign subcommand was parsed. Returns the exit status.
int run_campaign_command(const CLI::App& app, const CampaignArgs& args, const Ranks& ranks);

/// `jam campaign run` (app/campaign_run_command.cpp): its options, and the runs (with
/// --until-decided, the sequence of design/until_decided.hpp).
void add_campaign_run(CLI::App* campaign, CampaignArgs& args);
int run_campaign_run(const CLI::App* run, const CampaignArgs& args, const Ranks& ranks);

}  // namespace jam
