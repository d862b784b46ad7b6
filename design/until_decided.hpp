#pragma once
// `jam campaign run FILE --until-decided --budget CORE_HOURS`: run the campaign, judge it,
// add samples to the ensembles behind undecided verdicts, judge again, until every verdict is
// decided or the budget is spent. Looks are judged with Bonferroni alpha spending
// (checks/sequential.hpp); a verdict decided at a look is final.
//
// State: <output>/until-decided.json (the looks so far, the verdicts decided and at which look,
// the samples per ensemble for the next runs) and <output>/added-samples.toml (what the
// planners read, campaign/added_samples.hpp), both written atomically, the state first. A run
// killed at any point resumes where it was: the runs by their checkpoints, the looks from the
// state, so the same command gives the same files. Under MPI rank 0 judges and the ranks run
// every batch together; with --shard each share runs its runs, shard 1 judges once every run of
// the look is done and the others wait for its decision.
//
// Files: until_decided.cpp (the looks in turn, the shards' waits, the budget),
// until_decided_look.cpp (one look), until_decided_state.cpp (the state),
// until_decided_options.cpp (what a sequence is judged with), sequence_cost.cpp.
#include <optional>

#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"
#include "campaign/ranks.hpp"

namespace jam::design {

struct UntilDecidedOptions {
  double budget_core_hours = 0;  // core-hours all runs of the directory may take, in all
  double alpha = 0.05;           // of the whole sequence of looks
  // The range asked (the region "asked"): --phi-min/--phi-max, replacing the campaign's
  // [question] phi_min/phi_max. With a range asked, only the verdicts of that range drive the
  // samples added; the others are judged and reported as they stand.
  std::optional<double> phi_min, phi_max;
  double poll_seconds = 2;  // --shard: how often the shards look at each other's work
};

/// Throws CLI-style std::invalid_argument naming --budget when it is not finite and > 0.
void validate_until_decided(const UntilDecidedOptions& o);

/// The question a sequence judges: the campaign's [question], its range's ends replaced by
/// --phi-min/--phi-max. Throws std::invalid_argument naming the option and value when they
/// leave no range, or only one end with no question to take the other from.
CampaignQuestion sequence_question(const Campaign& c, const UntilDecidedOptions& o);

/// Returns the exit status: that of the runs when they fail (1) or are interrupted (130);
/// else that of `jam check` on the final verdicts (0 all pass, 1 a failure, 3 undecided).
int run_until_decided(const Campaign& campaign, const CampaignRunOptions& run,
                      const UntilDecidedOptions& o, const Ranks& ranks);

}  // namespace jam::design
