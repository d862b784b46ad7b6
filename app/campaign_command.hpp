#pragma once
#include <CLI/CLI.hpp>

#include "app/until_decided.hpp"
#include "campaign/campaign_runner.hpp"
#include "campaign/convergence_campaign.hpp"
#include "campaign/external_campaign.hpp"

namespace jam {

struct CampaignArgs {
  std::string file;       // campaign TOML (run, plan)
  std::string directory;  // campaign directory (status)
  CampaignRunOptions run;
  bool json = false;  // status --json
  std::string shard;  // run --shard K/N
  bool until_decided = false;
  UntilDecidedOptions until;              // --budget, --alpha
  std::vector<std::string> scatter_from;  // plan --scatter-from DIR...
  int pilot = 0;                          // plan --pilot K
  bool probe = false;                     // plan --probe
  std::vector<std::string> import_files;  // import DIR FILE...
  ImportOptions import_options;
  ConvergenceChoice converge;  // converge FILE: what is redone
  std::string converge_out;    // converge --out: the campaign file written
};

/// Registers `jam campaign run|status|plan`.
void add_campaign_command(CLI::App& app, CampaignArgs& args);

/// Runs whichever campaign subcommand was parsed. Returns the exit status.
int run_campaign_command(const CLI::App& app, const CampaignArgs& args, const Ranks& ranks);

}  // namespace jam
