#include <fmt/format.h>

#include <stdexcept>
#include <tuple>

#include "app/campaign_command.hpp"
#include "app/shard_option.hpp"

namespace jam {

void add_campaign_run(CLI::App* campaign, CampaignArgs& a) {
  CLI::App* run = campaign->add_subcommand(
      "run", "Run every missing run (resumes partial ones); under mpirun the ranks share them");
  run->option_defaults()->always_capture_default();
  run->add_option("file", a.file, "Campaign file (TOML, see reference/campaigns/)")->required();
  run->add_option("--jobs", a.run.jobs, "Runs at once per process (0 = all cores)");
  run->add_flag("--retry-failed", a.run.retry_failed, "Also redo runs whose last attempt failed");
  run->add_flag("--quiet", a.run.quiet, "No progress display and no summary");
  run->add_option("--log-every", a.run.log_seconds,
                  "Without a terminal (a batch log): a progress line every this many seconds")
      ->check(CLI::Range(0.1, 86400.0));
  run->add_option("--shard", a.shard,
                  "K/N: run only the K-th of N disjoint shares of the campaign (whole samples, "
                  "balanced by cost; K from 1), e.g. one per Slurm array task; together the N "
                  "shares are the whole campaign, bitwise. 'auto': this Slurm array task's "
                  "share, whatever the array's first index (--array=0-31 or 1-32, steps too)");
  run->add_flag("--force", a.run.force,
                "Run even runs beyond the per-run limits on steps, output points and memory");
  run->add_flag("--until-decided", a.until_decided,
                "Then judge the checks, add samples to the ensembles of undecided verdicts and "
                "judge again, until every verdict is decided or --budget is spent (alpha "
                "spent over the looks: docs/statistics-and-checks.md#until-decided)");
  run->add_option("--budget", a.until.budget_core_hours,
                  "--until-decided: core-hours all runs of the campaign may take, in all");
  run->add_option("--alpha", a.until.alpha,
                  "--until-decided: false-alarm rate of each check over all looks (default: the "
                  "campaign file's [question] alpha, else 0.05)")
      ->check(CLI::Range(1e-6, 0.5));
  run->add_option("--phi-min", a.until.phi_min,
                  "--until-decided: the range asked from this packing, judged as the region "
                  "\"asked\" (default: the campaign file's [question] phi_min); with a range "
                  "asked only its verdicts drive the samples added")
      ->always_capture_default(false);
  run->add_option("--phi-max", a.until.phi_max,
                  "--until-decided: the range asked up to this packing (default: [question] "
                  "phi_max)")
      ->always_capture_default(false);
}

int run_campaign_run(const CLI::App* run, const CampaignArgs& a, const Ranks& ranks) {
  CampaignRunOptions options = a.run;
  if (!a.shard.empty()) std::tie(options.shard, options.shards) = parse_shard(a.shard);
  if (a.until_decided) {
    try {
      design::validate_until_decided(a.until);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--budget", e.what());
    }
    const Campaign c = read_campaign(a.file);
    design::UntilDecidedOptions until = a.until;
    // The campaign's question is the default; the command line's --alpha overrides it.
    if (!run->count("--alpha") && c.question.alpha) until.alpha = *c.question.alpha;
    try {
      design::sequence_question(c, until);  // a range that is none: one line, before any run
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError(e.what());
    }
    return design::run_until_decided(c, options, until, ranks);
  }
  if (run->count("--budget") || run->count("--alpha") || run->count("--phi-min") ||
      run->count("--phi-max"))
    throw CLI::ValidationError(
        "--budget", "--budget, --alpha, --phi-min and --phi-max go with --until-decided");
  return run_campaign(read_campaign(a.file), options, ranks);
}

}  // namespace jam
